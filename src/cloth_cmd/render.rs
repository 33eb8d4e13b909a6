//! PNG files of cloth frames: [`cloth::render`] draws the picture,
//! [`compare::plot::captioned_png`] writes it with its caption (the cloth
//! crate has no image library).

use std::path::Path;

use anyhow::{Context, Result};
use cloth::Vec3;
use cloth::render::rasterise;

pub use cloth::render::{Camera, Stage};

/// Render the cloth at `positions` (all particles, by id) to a PNG file;
/// a note when the picture left triangles out
/// (the pixel budget, [`cloth::render::PIXEL_BUDGET_PER_PIXEL`]); the
/// caption says so too.
pub fn render_png_noted(
    path: &Path,
    stage: &Stage,
    camera: &Camera,
    positions: &[Vec3],
    caption: &str,
) -> Result<Option<String>> {
    let picture = rasterise(stage, camera, positions);
    let caption = picture.caption(caption);
    let note = picture.simplified.as_ref().map(ToString::to_string);
    let image = picture.image;
    compare::plot::captioned_png(path, (image.width, image.height), image.rgb, &caption)
        .with_context(|| format!("{}: cannot write the PNG", path.display()))?;
    Ok(note)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit square at height `y`: four particles, two triangles (the
    /// rasteriser's own tests draw finer sheets; these test the PNG).
    fn square(y: f64) -> (Vec<Vec3>, Vec<[usize; 3]>) {
        let pts = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
            .map(|(x, z)| Vec3::new(x, y, z))
            .to_vec();
        (pts, vec![[0, 1, 3], [0, 3, 2]])
    }

    #[test]
    fn a_simplified_picture_says_so() {
        // 20 000 triangles that each cover a large part of the picture.
        let (pts, _) = square(0.0);
        let big = [[0, 1, 3], [0, 3, 2]];
        let stage = Stage {
            colliders: vec![],
            triangles: big.iter().copied().cycle().take(20_000).collect(),
            nx: 2,
        };
        let camera = Camera::fit(&pts, &[]);
        let dir = std::env::temp_dir().join(format!("symlab-render-budget-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let note = render_png_noted(&dir.join("x.png"), &stage, &camera, &pts, "test").unwrap();
        let note = note.expect("the budget ran out");
        assert!(note.contains("not drawn"), "{note}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_png_is_written() {
        let (pts, triangles) = square(1.0);
        let stage = Stage {
            colliders: vec![],
            triangles,
            nx: 2,
        };
        let camera = Camera::fit(&pts, &stage.colliders);
        let dir = std::env::temp_dir().join(format!("symlab-render-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("x.png");
        render_png_noted(&path, &stage, &camera, &pts, "test").unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
