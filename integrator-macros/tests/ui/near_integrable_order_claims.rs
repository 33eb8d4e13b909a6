use integrator_macros::butcher;

// Laskar–Robutel SABA₃ has generalised order (6, 2): claiming (8, 2) fails
// at the first condition past the truth, εh⁷.
butcher! {
    pub Saba3OverClaim {
        let c1 = 1/2 - sqrt(15)/10;
        let c2 = sqrt(15)/10;
        claims: [symplectic, order = 2, order = (8, 2)],
        drift: [c1, c2, c2, c1],
        kick: [5/18, 4/9, 5/18],
    }
}

// SABA₂ with its kicks moved by ±1/1000 (still consistent, no longer
// symmetric): the Lie term [A, B] survives.
butcher! {
    pub Saba2Perturbed {
        let c1 = 1/2 - sqrt(3)/6;
        claims: [symplectic, order = (4, 2)],
        drift: [c1, sqrt(3)/3, c1],
        kick: [1/2 + 1/1000, 1/2 - 1/1000],
    }
}

// SABA₂ is (4, 2), not (4, 4): the ε² part fails at ε²h³.
butcher! {
    pub Saba2SecondPart {
        let c1 = 1/2 - sqrt(3)/6;
        claims: [order = (4, 4)],
        drift: [c1, sqrt(3)/3, c1],
        kick: [1/2, 1/2],
    }
}

// Strang splitting is (2, 2): a generalised order may increase (SABAC₁ is
// (2, 4)), but Strang's ε² part fails at ε²h³ ([[A, B], B]).
butcher! {
    pub Increasing {
        claims: [order = (2, 4)],
        drift: [1/2, 1/2],
        kick: [1],
    }
}

// A Runge–Kutta table has no near-integrable order.
butcher! {
    pub Rk2 {
        claims: [order = (2, 2)],
        a: [[0, 0], [1/2, 0]],
        b: [0, 1],
    }
}

fn main() {}
