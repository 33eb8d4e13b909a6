//! The same scene at another resolution.

use std::collections::BTreeSet;

use super::{Scene, grid_too_large};

/// Why a grid text was refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum GridError {
    #[error("expected NX×NY with both at least 2, e.g. 64x64 (got \"{0}\")")]
    Syntax(String),
    #[error("{0}")]
    TooLarge(String),
}

/// `"64x64"`, `"64×32"` or `"64"` (square) → `(nx, ny)`, both at least 2
/// and within [`MAX_PARTICLES`](super::MAX_PARTICLES) together.
pub fn parse_grid(text: &str) -> Result<(usize, usize), GridError> {
    let parts: Vec<&str> = text.split(['x', 'X', '×']).collect();
    let parse = |s: &str| s.trim().parse::<usize>().ok().filter(|&n| n >= 2);
    let (nx, ny) = match parts.as_slice() {
        [n] => parse(n).map(|n| (n, n)),
        [a, b] => parse(a).zip(parse(b)),
        _ => None,
    }
    .ok_or_else(|| GridError::Syntax(text.to_string()))?;
    if let Some((_, message)) = grid_too_large(nx, ny) {
        return Err(GridError::TooLarge(message));
    }
    Ok((nx, ny))
}

/// The scene at `nx × ny` particles, otherwise unchanged (same size,
/// material and pins): pinned edges stay pinned edges, other pins
/// (corners, points) move to the nearest particle at the same place. The
/// caller validates the result ([`Scene::validate`]).
pub fn regrid(scene: &mut Scene, nx: usize, ny: usize) {
    let (nx0, ny0) = (scene.cloth.nx, scene.cloth.ny);
    let old: BTreeSet<(usize, usize)> = scene.pins.iter().copied().collect();
    let edges = [
        (0..nx0).all(|i| old.contains(&(i, 0))),
        (0..nx0).all(|i| old.contains(&(i, ny0 - 1))),
        (0..ny0).all(|j| old.contains(&(0, j))),
        (0..ny0).all(|j| old.contains(&(nx0 - 1, j))),
    ];
    let on_full_edge = |&(i, j): &(usize, usize)| {
        (edges[0] && j == 0)
            || (edges[1] && j == ny0 - 1)
            || (edges[2] && i == 0)
            || (edges[3] && i == nx0 - 1)
    };
    let mut pins = BTreeSet::new();
    if edges[0] {
        pins.extend((0..nx).map(|i| (i, 0)));
    }
    if edges[1] {
        pins.extend((0..nx).map(|i| (i, ny - 1)));
    }
    if edges[2] {
        pins.extend((0..ny).map(|j| (0, j)));
    }
    if edges[3] {
        pins.extend((0..ny).map(|j| (nx - 1, j)));
    }
    let map =
        |k: usize, n0: usize, n: usize| ((k * (n - 1)) as f64 / (n0 - 1) as f64).round() as usize;
    pins.extend(
        old.iter()
            .filter(|p| !on_full_edge(p))
            .map(|&(i, j)| (map(i, nx0, nx), map(j, ny0, ny))),
    );
    scene.pins = pins.into_iter().collect();
    scene.cloth.nx = nx;
    scene.cloth.ny = ny;
}
