use integrator_macros::butcher;

// The triple jump with x rounded to 16 digits: order 4 holds only to a
// residual, so an unbounded claim is rejected.
butcher! {
    pub RoundedTripleJump {
        claims: [order = 4],
        compose: [1.3512071919596576, -1.7024143839193152, 1.3512071919596576],
    }
}

fn main() {}
