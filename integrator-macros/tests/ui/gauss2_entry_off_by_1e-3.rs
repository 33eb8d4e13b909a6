use integrator_macros::butcher;

butcher! {
    pub AlmostGauss2 {
        claims: [symplectic],
        a: [[1/4, 1/4 - sqrt(3)/6 + 1/1000],
            [1/4 + sqrt(3)/6, 1/4]],
        b: [1/2, 1/2],
    }
}

fn main() {}
