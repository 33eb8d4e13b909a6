use integrator_macros::butcher;

// Störmer–Verlet has order 2 on Runge–Kutta–Nyström systems too.
butcher! {
    pub Verlet {
        claims: [symplectic, order = 2, order_rkn = 3],
        drift: [1/2, 1/2],
        kick: [1],
    }
}

// Beyond the checker's RKN limit: refused, never accepted unchecked.
butcher! {
    pub VerletHigh {
        claims: [order_rkn = 15 (residual < 1e-10)],
        drift: [1/2, 1/2],
        kick: [1],
    }
}

// A misspelt keyword.
butcher! {
    pub VerletTypo {
        claims: [order_rnk = 2],
        drift: [1/2, 1/2],
        kick: [1],
    }
}

fn main() {}
