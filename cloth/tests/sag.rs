//! `cloth.sag`: rows that start as circular arcs, so that a cloth can hang
//! between two pinned edges (a hammock) on its constraints.

use cloth::{RunSettings, Scene, Simulation, scene::max_sag};

fn hammock(sag: &str, stretch: &str, pins: &str, n: usize) -> String {
    format!(
        r#"
        gravity = [0.0, -9.6610, 1.7035]
        [cloth]
        width = 1.0
        height = 0.5
        nx = {n}
        ny = 6
        plane = "horizontal"
        sag = {sag}
        [material]
        density = 0.01378
        stretch = {stretch}
        shear = 0.002
        [pins]
        edges = {pins}
        [simulation]
        substeps = 4
        frames = 30
        method = "{method}"
    "#,
        method = if stretch.contains("inextensible") {
            "rattle"
        } else {
            "symplectic-euler-a"
        }
    )
}

fn scene(toml: &str) -> Scene {
    Scene::from_toml(toml, "hammock.toml").unwrap()
}

fn error(toml: &str) -> String {
    Scene::from_toml(toml, "hammock.toml")
        .and_then(|s| Simulation::new(&s).map(|_| ()))
        .unwrap_err()
        .to_string()
}

#[test]
fn sagged_rows_are_arcs_of_chords_of_the_grid_spacing() {
    for (n, sag) in [(9, 0.25), (25, 0.1), (25, 0.3), (64, 1e-3)] {
        let s = scene(&hammock(
            &sag.to_string(),
            r#""inextensible""#,
            r#"["left", "right"]"#,
            n,
        ));
        let sim = Simulation::new(&s).expect("a hammock starts on its constraints");
        let x = sim
            .model
            .positions(&sim.model.initial_state()[..3 * sim.model.free_count()]);
        let dx = 1.0 / (n - 1) as f64;
        for j in 0..6 {
            let row = &x[j * n..(j + 1) * n];
            for w in row.windows(2) {
                let chord = (w[1] - w[0]).norm();
                assert!(
                    (chord - dx).abs() <= 4.0 * f64::EPSILON,
                    "chord {chord} ≠ {dx}"
                );
            }
            // Both ends at height 0, the lowest particle at most `sag` below
            // them (exactly, for an odd `n`: the middle one) and within a
            // chord of the arc's lowest point.
            assert_eq!((row[0].y, row[n - 1].y), (0.0, 0.0));
            let low = -row.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
            assert!(
                low <= sag * (1.0 + 1e-12) && low >= sag - dx,
                "n = {n}: {low}, {sag}"
            );
            if n % 2 == 1 {
                assert!((low - sag).abs() <= 1e-12 * sag, "n = {n}: {low}, {sag}");
            }
            // The span shrinks, the rows stay in their plane z = j·Δz.
            assert!(row[n - 1].x < 1.0 && row[n - 1].x > 0.5);
            assert!(row.iter().all(|p| p.z == row[0].z));
        }
    }
}

#[test]
fn no_sag_is_the_flat_grid_bit_for_bit() {
    let springs = hammock("0.0", "50.75", r#"["left"]"#, 9);
    let flat = springs.replace("sag = 0.0", "");
    let a = Simulation::new(&scene(&springs)).unwrap();
    let b = Simulation::new(&scene(&flat)).unwrap();
    assert_eq!(a.model.initial_state(), b.model.initial_state());
}

#[test]
fn a_hammock_needs_its_sag_and_at_most_a_half_circle() {
    // Flat, every row is a straight line of edges taut between two pins.
    let e = error(&hammock(
        "0.0",
        r#""inextensible""#,
        r#"["left", "right"]"#,
        9,
    ));
    assert!(e.contains("pins") && e.contains("dependent"), "{e}");
    let most = max_sag(9, 1.0 / 8.0);
    assert!((most - 0.125 / (2.0 * (std::f64::consts::PI / 16.0).sin())).abs() < 1e-15);
    assert!(
        Simulation::new(&scene(&hammock(
            &most.to_string(),
            r#""inextensible""#,
            r#"["left", "right"]"#,
            9
        )))
        .is_ok()
    );
    let e = error(&hammock(
        &(most * 1.01).to_string(),
        r#""inextensible""#,
        r#"["left", "right"]"#,
        9,
    ));
    assert!(e.contains("cloth.sag") && e.contains("half circle"), "{e}");
    let e = error(&hammock(
        "-0.1",
        r#""inextensible""#,
        r#"["left", "right"]"#,
        9,
    ));
    assert!(e.contains("cloth.sag"), "{e}");
    let e = error(&hammock(
        "\"deep\"",
        r#""inextensible""#,
        r#"["left", "right"]"#,
        9,
    ));
    assert!(e.contains("cloth.sag"), "{e}");
}

#[test]
fn a_sagging_spring_cloth_starts_with_its_stretch_and_shear_springs_at_rest() {
    // Chords of the grid spacing, and the shear diagonals across a chord
    // and a straight warp edge are √2·Δ as on the flat grid: no elastic
    // energy at the start.
    let s = scene(&hammock("0.2", "50.75", r#"["left", "right"]"#, 17));
    let sim = Simulation::new(&s).unwrap();
    let e = sim.model.energy(&sim.model.initial_state());
    let scale = sim.model.particle_mass() * 9.81 * sim.model.particle_count() as f64;
    assert!(e.springs.abs() < 1e-24 * scale, "{}", e.springs);
}

#[test]
fn a_swinging_hammock_keeps_its_constraints_and_its_energy() {
    let s = scene(&hammock(
        "0.25",
        r#""inextensible""#,
        r#"["left", "right"]"#,
        13,
    ));
    let mut sim = Simulation::new(&s).unwrap();
    let h0 = sim.model.energy(&sim.model.initial_state()).total();
    let e_ref = sim.model.particle_mass() * sim.model.free_count() as f64 * 9.81 * 1.0;
    let mut worst: f64 = 0.0;
    let mut moved: f64 = 0.0;
    let x0 = sim
        .model
        .positions(&sim.model.initial_state()[..3 * sim.model.free_count()]);
    let settings = RunSettings::from_scene(&s);
    sim.run(&cloth::Method::parse("rattle").unwrap(), &settings, |f| {
        worst = worst.max((f.model.energy(f.state).total() - h0).abs() / e_ref);
        let x = f.positions();
        for (a, b) in x.iter().zip(&x0) {
            moved = moved.max((a - b).norm());
        }
        Ok(())
    })
    .unwrap();
    // It swings (10° from hanging), and its energy error stays at the
    // level of RATTLE's O(h²) oscillation.
    assert!(moved > 0.02, "moved {moved}");
    assert!(worst < 1e-4, "energy error {worst}");
}

#[test]
fn the_shipped_hammock_loads_and_swings_on_its_constraints() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes/hammock-inextensible.toml");
    let mut s = Scene::load(&path).unwrap();
    assert_eq!(s.cloth.sag, 0.25);
    assert_eq!(s.simulation.frames, 36_000, "ten minutes at 60 Hz");
    s.simulation.frames = 20;
    let mut sim = Simulation::new(&s).unwrap();
    let n = 3 * sim.model.free_count();
    let settings = RunSettings::from_scene(&s);
    sim.run(&cloth::Method::parse("rattle").unwrap(), &settings, |f| {
        assert!(f.model.constraint_residual(&f.state[..n]).unwrap() <= cloth::CONSTRAINT_TOLERANCE);
        assert!(f.model.constraint_velocity_residual(f.state).unwrap() <= 1e-12);
        Ok(())
    })
    .unwrap();
}
