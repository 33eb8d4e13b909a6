use integrator_macros::butcher;

// The Wisdom–Holman leapfrog with the corrector of order 3 has the
// effective generalised order (4, 2): claiming (6, 2) fails at the first
// condition past the truth, εh⁵, of the effective method χ K χ⁻¹.
butcher! {
    pub CorrectedOverClaim {
        let a = sqrt(7/40);
        let b = -1/96*sqrt(40/7);
        claims: [symplectic, order = (6, 2)],
        kernel: "leapfrog",
        corrector_drift: [a, -2*a, a - a, 2*a, -a],
        corrector_kick: [-b, b, b, -b],
    }
}

// The same corrector with b moved in its 4th digit: the kernel's εh³ term
// is no longer removed.
butcher! {
    pub CorrectorPerturbed {
        let a = sqrt(7/40);
        let b = -1/96*sqrt(40/7) + 1/100000;
        claims: [order = (4, 2)],
        drift: [1/2, 1/2],
        kick: [1],
        corrector_drift: [a, -2*a, a - a, 2*a, -a],
        corrector_kick: [-b, b, b, -b],
    }
}

// A corrector processes a drift–kick sequence, not a Runge–Kutta table.
butcher! {
    pub CorrectedRk {
        claims: [order = 2],
        a: [[0, 0], [1/2, 0]],
        b: [0, 1],
        corrector_drift: [1, -1],
        corrector_kick: [1],
    }
}

// A catalogue processed method is not a kernel.
butcher! {
    pub Nested {
        kernel: "leapfrog-c3",
        corrector_drift: [1, -1],
        corrector_kick: [1],
    }
}

fn main() {}
