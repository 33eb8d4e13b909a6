//! Frame output: Wavefront OBJ meshes and the one per-frame table,
//! `energy.csv`.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use nalgebra::Vector3;

use crate::run::FrameStats;
use crate::study::energy::relative_errors;

/// An output file that could not be written.
#[derive(Debug, thiserror::Error)]
#[error("{}: cannot write: {source}", path.display())]
pub struct OutputError {
    pub path: PathBuf,
    #[source]
    pub source: io::Error,
}

fn to_file(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>,
) -> Result<(), OutputError> {
    let wrap = |source| OutputError {
        path: path.to_path_buf(),
        source,
    };
    let mut out = BufWriter::new(File::create(path).map_err(wrap)?);
    write(&mut out).map_err(wrap)?;
    out.flush().map_err(wrap)
}

/// Write a triangle mesh as OBJ (`v` lines, then 1-based `f` lines).
pub fn write_obj_to(
    out: &mut impl Write,
    positions: &[Vector3<f64>],
    triangles: &[[usize; 3]],
) -> io::Result<()> {
    for x in positions {
        writeln!(out, "v {} {} {}", x.x, x.y, x.z)?;
    }
    for t in triangles {
        writeln!(out, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1)?;
    }
    Ok(())
}

/// Write a triangle mesh to an OBJ file; errors name the file.
///
/// ```no_run
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let scene = cloth::Scene::load("scenes/paper.toml")?;
/// let model = cloth::ClothModel::new(&scene)?;
/// let z = model.initial_state();
/// let q = &z[..z.len() / 2];
/// cloth::write_obj("frame0000.obj", &model.positions(q), &model.triangles())?;
/// # Ok(()) }
/// ```
pub fn write_obj(
    path: impl AsRef<Path>,
    positions: &[Vector3<f64>],
    triangles: &[[usize; 3]],
) -> Result<(), OutputError> {
    to_file(path.as_ref(), |out| write_obj_to(out, positions, triangles))
}

/// The header of `energy.csv` ([`write_energy_csv`]): the energy split,
/// the relative energy error `(H − H₀)/E_ref`, the potential's terms, the
/// momentum and the largest strain.
pub const ENERGY_CSV_HEADER: &str = "frame,step,time,kinetic,potential,total,relative_energy_error,springs,gravity,colliders,momentum_x,momentum_y,momentum_z,max_strain";

/// Write per-frame statistics as `energy.csv` (header
/// [`ENERGY_CSV_HEADER`]), relative errors against `e_ref`
/// ([`reference_energy`](crate::study::energy::reference_energy)).
pub fn write_energy_csv_to(
    out: &mut impl Write,
    frames: &[FrameStats],
    e_ref: f64,
) -> io::Result<()> {
    writeln!(out, "{ENERGY_CSV_HEADER}")?;
    for (f, rel) in frames.iter().zip(relative_errors(frames, e_ref)) {
        let e = &f.energy;
        writeln!(
            out,
            "{},{},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
            f.frame,
            f.step,
            f.time,
            e.kinetic,
            e.potential(),
            e.total(),
            rel,
            e.springs,
            e.gravity,
            e.colliders,
            f.momentum.x,
            f.momentum.y,
            f.momentum.z,
            f.max_strain
        )?;
    }
    Ok(())
}

/// [`write_energy_csv_to`] a file; errors name the file.
pub fn write_energy_csv(
    path: impl AsRef<Path>,
    frames: &[FrameStats],
    e_ref: f64,
) -> Result<(), OutputError> {
    to_file(path.as_ref(), |out| write_energy_csv_to(out, frames, e_ref))
}
