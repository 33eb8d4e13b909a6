use integrator_macros::butcher;

butcher! {
    pub Unbound {
        let x = 1/2;
        a: [[y]],
        b: [1],
    }
}

fn main() {}
