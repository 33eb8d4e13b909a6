use integrator_macros::butcher;

butcher! {
    /// Gauss–Legendre 2 via roots has order 4, not 5: the claim is decided
    /// on the trees in the number field and refused naming the first tree
    /// whose condition fails.
    pub Gauss2Roots {
        let c0 = root(6*x^2 - 6*x + 1, 0, 1/2);
        let c1 = root(6*x^2 - 6*x + 1, 1/2, 1);
        claims: [symplectic, order = 5],
        a: [[1/4, c0 - 1/4], [c1 - 1/4, 1/4]],
        b: [1/2, 1/2],
    }
}

fn main() {}
