use integrator_macros::butcher;

butcher! {
    pub LobattoIIIA2 {
        claims: [symplectic],
        a: [[0, 0], [1/2, 1/2]],
        b: [1/2, 1/2],
    }
}

fn main() {}
