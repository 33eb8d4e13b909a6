use integrator_core::butcher;

butcher! {
    pub Imaginary {
        a: [[sqrt(-2)]],
        b: [1],
    }
}

fn main() {}
