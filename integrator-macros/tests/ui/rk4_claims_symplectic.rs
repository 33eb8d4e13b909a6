use integrator_macros::butcher;

butcher! {
    pub Rk4 {
        claims: [symplectic, order = 4],
        a: [[0, 0, 0, 0], [1/2, 0, 0, 0], [0, 1/2, 0, 0], [0, 0, 1, 0]],
        b: [1/6, 1/3, 1/3, 1/6],
    }
}

fn main() {}
