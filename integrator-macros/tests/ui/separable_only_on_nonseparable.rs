// A drift–kick sequence is symplectic only for separable Hamiltonians, so
// it must not step one that is not: `NonSeparable` implements `Hamiltonian`
// only.
use integrator_core::integrate;
use integrator_core::library::ForestRuth;
use integrator_core::problems::NonSeparable;

fn main() {
    let sys = NonSeparable { eps: 0.5 };
    let mut z = [1.0, 0.0, 0.0, 1.0];
    let _ = integrate(&ForestRuth, &sys, &mut z, 0.0, 0.1, 10, |_, _, _| {});
}
