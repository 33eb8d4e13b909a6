use integrator_macros::butcher;

butcher! {
    pub Rk4 {
        claims: [order = 4],
        a: [[0, 0, 0, 0], [1/2, 0, 0, 0], [0, 1/2, 0, 0], [0, 0, 1, 0]],
        b: [1/6, 1/3, 1/3, 1/6],
        c: [0, 1/2, 1/2, 1/2],
    }
}

fn main() {}
