use integrator_macros::butcher;

butcher! {
    pub Heun {
        claims: [order = 3],
        a: [[0, 0], [1, 0]],
        b: [1/2, 1/2],
    }
}

fn main() {}
