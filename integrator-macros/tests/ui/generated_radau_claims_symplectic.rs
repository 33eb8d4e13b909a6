use integrator_macros::butcher;

butcher! {
    /// Radau IIA with 4 stages is A-stable and of order 7, but not symplectic.
    pub Radau4 {
        claims: [symplectic, order = 8],
        from: "radau2a4",
    }
}

fn main() {}
