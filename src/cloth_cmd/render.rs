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
