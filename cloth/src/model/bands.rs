//! The force of a band of grid rows, for the banded stepper
//! ([`crate::step::banded`]): the stencil's row loops restricted to the
//! band's particles ([`Stencil::rows`](super::stencil::Stencil::rows)), and
//! the colliders' push on them. Positions and forces are arrays over the
//! grid's particles (pinned ones included) by particle id `j·nx + i`.

use std::ops::Range;

use nalgebra::Vector3;

use super::ClothModel;

impl ClothModel {
    /// The springs' force on the particles of rows `rows` into `force`
    /// (`force[c][k]`: particle `rows.start·nx + k`), from the grid's
    /// positions `pos`, which must be current in the rows the band's
    /// springs reach ([`spring_reach`](Self::spring_reach) above and below).
    /// Each particle's sum is the one the whole-grid kernel forms, to the
    /// bit; the springs crossing the band's edges are computed by both
    /// bands they touch.
    pub(crate) fn band_springs(
        &self,
        pos: &[&[f64]; 3],
        rows: Range<usize>,
        force: [&mut [f64]; 3],
        row: &mut [Vec<f64>; 3],
    ) {
        self.stencil.rows(pos, 0..self.ny, rows, force, row);
    }

    /// `force ← (weight + force) + Σ collider pushes` at the particles whose
    /// `free` is nonzero (pinned particles are left alone), in the order
    /// [`Separable::force`](integrator_core::Separable::force) adds them;
    /// `pos` holds the same particles' positions.
    pub(crate) fn band_colliders(&self, pos: [&[f64]; 3], free: &[f64], force: [&mut [f64]; 3]) {
        let [fx, fy, fz] = force;
        let w = self.weight;
        for (k, &m) in free.iter().enumerate() {
            if m == 0.0 {
                continue;
            }
            let x = Vector3::new(pos[0][k], pos[1][k], pos[2][k]);
            let mut f = Vector3::new(w[0] + fx[k], w[1] + fy[k], w[2] + fz[k]);
            for c in &self.colliders {
                f += c.force(&x);
            }
            (fx[k], fy[k], fz[k]) = (f.x, f.y, f.z);
        }
    }
}
