use integrator_core::butcher;

// A drift–kick sequence with gradient kicks (the WHCKL kernel, D(1/2)
// G(1, 1/24) D(1/2)) is refused: butcher! generates no step code for the
// kick of V − g·h²·|∇V|², and never steps it with plain kicks.
butcher! {
    pub LazyKernel {
        claims: [symplectic],
        drift: [1/2, 1/2],
        kick: [1],
        kick_gradient: [1/24],
    }
}

// The catalogue's WHCKL (with its corrector) is refused the same way.
butcher! {
    pub Whckl {
        from: "whckl-c17",
    }
}

fn main() {}
