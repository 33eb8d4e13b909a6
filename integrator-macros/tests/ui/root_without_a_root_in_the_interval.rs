use integrator_macros::butcher;

butcher! {
    /// The nodes of Gauss–Legendre 2 are (3 ∓ √3)/6 ≈ 0.211, 0.789: none in (0, 1/10].
    pub NoRoot {
        let c0 = root(6*x^2 - 6*x + 1, 0, 1/10);
        let c1 = root(6*x^2 - 6*x + 1, 1/2, 1);
        claims: [symplectic],
        a: [[1/4, c0 - 1/4], [c1 - 1/4, 1/4]],
        b: [1/2, 1/2],
    }
}

fn main() {}
