//! The springs of the grid: the two flat lists the list loops walk
//! (free–free, free–pinned) and the order in which the grid hands them out.

use super::Family;

/// A spring between two free particles (indices into the free list).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Spring {
    pub(crate) a: u32,
    pub(crate) b: u32,
    /// `k/L` (N/m).
    pub(crate) kl: f64,
    /// Rest length `L` (m).
    pub(crate) rest: f64,
}

/// A spring between a free particle and a pinned one.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PinSpring {
    pub(crate) a: u32,
    pub(crate) pin: [f64; 3],
    pub(crate) kl: f64,
    pub(crate) rest: f64,
}

/// The springs of a grid, as `(particle a, particle b, family, rest length)`
/// with particle ids `j·nx + i`, handed to `each` in the order the model
/// stores them: family by family and direction by direction, row by row,
/// and within a row of horizontal springs alternating blocks so that
/// consecutive springs share no particle. A callback rather than a list:
/// on a 2048 × 2048 grid the list alone would be 24 million entries.
pub(super) fn grid_springs(
    nx: usize,
    ny: usize,
    dx: f64,
    dy: f64,
    families: [bool; 3],
    mut each: impl FnMut(usize, usize, Family, f64),
) {
    let id = |i: usize, j: usize| j * nx + i;
    for (di, dj, family, rest) in directions(dx, dy, families) {
        let is: Vec<usize> = (0..nx)
            .filter(|&i| {
                let ib = i as isize + di;
                ib >= 0 && (ib as usize) < nx
            })
            .collect();
        // Horizontal springs: blocks of `di` starting points alternate so
        // that consecutive springs are disjoint.
        let order: Vec<usize> = if dj == 0 {
            let l = di.unsigned_abs();
            let first = is.iter().copied().filter(|i| (i / l) % 2 == 0);
            let second = is.iter().copied().filter(|i| (i / l) % 2 == 1);
            first.chain(second).collect()
        } else {
            is
        };
        for j in 0..ny.saturating_sub(dj as usize) {
            for &i in &order {
                let ib = (i as isize + di) as usize;
                each(id(i, j), id(ib, j + dj as usize), family, rest);
            }
        }
    }
}

/// The spring directions of a grid with spacing `dx`, `dy` and the
/// families present: `(di, dj, family, rest length)`, a spring joining
/// particle `(i, j)` to `(i + di, j + dj)` wherever both exist. The one
/// place that knows the grid's stencil (the spring lists and the stencil
/// kernel both read it).
pub(super) fn directions(
    dx: f64,
    dy: f64,
    families: [bool; 3],
) -> Vec<(isize, isize, Family, f64)> {
    let diag = dx.hypot(dy);
    let mut dirs = Vec::new();
    if families[0] {
        dirs.extend([(1, 0, Family::Stretch, dx), (0, 1, Family::Stretch, dy)]);
    }
    if families[1] {
        dirs.extend([(1, 1, Family::Shear, diag), (-1, 1, Family::Shear, diag)]);
    }
    if families[2] {
        dirs.extend([
            (2, 0, Family::Bend, 2.0 * dx),
            (0, 2, Family::Bend, 2.0 * dy),
        ]);
    }
    dirs
}
