use integrator_macros::butcher;

butcher! {
    pub Imaginary {
        a: [[sqrt(-2)]],
        b: [1],
    }
}

fn main() {}
