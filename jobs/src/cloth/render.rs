//! PNG files of cloth frames: [`cloth::render`] draws the picture,
//! [`compare::plot::captioned_png`] writes it with its caption (the cloth
//! crate has no image library).

use std::path::Path;

use cloth::Vec3;
use cloth::render::rasterise;

use cloth::render::{Camera, Stage};

use super::request::JobError;

/// Render the cloth at `positions` (all particles, by id) to a PNG file;
/// a note when the picture left triangles out
/// (the pixel budget, [`cloth::render::PIXEL_BUDGET_PER_PIXEL`]); the
/// caption says so too.
pub fn png_noted(
    path: &Path,
    stage: &Stage,
    camera: &Camera,
    positions: &[Vec3],
    caption: &str,
) -> Result<Option<String>, JobError> {
    let picture = rasterise(stage, camera, positions);
    let caption = picture.caption(caption);
    let note = picture.simplified.as_ref().map(ToString::to_string);
    let image = picture.image;
    compare::plot::captioned_png(path, (image.width, image.height), image.rgb, &caption)
        .map_err(|e| JobError::Output(format!("{}: cannot write the PNG: {e}", path.display())))?;
    Ok(note)
}
