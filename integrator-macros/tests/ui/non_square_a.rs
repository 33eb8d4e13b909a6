use integrator_macros::butcher;

butcher! {
    pub Broken {
        a: [[1/2, 0], [1/2]],
        b: [1/2, 1/2],
    }
}

fn main() {}
