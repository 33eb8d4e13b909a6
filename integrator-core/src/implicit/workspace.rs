//! The workspaces: every buffer a step needs, made up front.

use std::fmt;

use super::dense::DenseLinear;
use super::iteration::{Caches, Core};
use super::settings::{Settings, Stats};
use super::sparse::SparseLinear;

/// Scratch memory, caches and counters of the dense stage solver
/// ([`step`](super::step)) for one system dimension and stage count.
///
/// The vectors are sized in [`new`](Self::new); the LU storage for a matrix
/// shape (the stacked `s·d × s·d` one, or a `d × d` stage matrix for DIRK
/// tables) is made the first time it is needed and then kept, so steps do
/// not allocate. Between steps it keeps the Jacobian and its
/// factorisations (see [`Settings::reuse_jacobian`]), the previous stage
/// derivatives (starting values), and the compensation of the summation.
pub struct ImplicitWorkspace {
    pub(crate) core: Core,
    pub(crate) linear: DenseLinear,
}

/// Scratch memory, caches and counters of the sparse stage solver
/// ([`step_sparse`](super::step_sparse)): as [`ImplicitWorkspace`], but the
/// stage matrices are faer sparse matrices on the Jacobian's pattern, with
/// their symbolic LU computed once (per matrix shape) and kept.
pub struct SparseWorkspace {
    pub(crate) core: Core,
    pub(crate) linear: SparseLinear,
}

macro_rules! common {
    ($ty:ident, $linear:ident) => {
        impl $ty {
            /// A workspace for systems of dimension `dim` and tables of
            /// `stages` stages, with the default [`Settings`].
            pub fn new(dim: usize, stages: usize) -> Self {
                $ty {
                    core: Core::new(dim, stages),
                    linear: $linear::new(dim, stages),
                }
            }

            /// The same workspace with other settings.
            pub fn with_settings(mut self, settings: Settings) -> Self {
                self.core.settings = settings;
                self
            }

            pub fn settings(&self) -> &Settings {
                &self.core.settings
            }

            /// Change the settings between steps.
            pub fn settings_mut(&mut self) -> &mut Settings {
                &mut self.core.settings
            }

            /// The counters.
            pub fn stats(&self) -> &Stats {
                &self.core.stats
            }

            pub fn reset_stats(&mut self) {
                self.core.stats = Stats::default();
            }

            /// Forget the previous steps: starting values, compensation,
            /// the Jacobian and its factorisations (the next step is solved
            /// as if it were the first).
            pub fn reset(&mut self) {
                self.core.reset();
                self.linear.reset();
            }

            /// The system dimension it was made for.
            pub fn dim(&self) -> usize {
                self.core.d
            }

            /// The number of stages it was made for.
            pub fn stages(&self) -> usize {
                self.core.s
            }
        }

        impl fmt::Debug for $ty {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.debug_struct(stringify!($ty))
                    .field("dim", &self.core.d)
                    .field("stages", &self.core.s)
                    .field("settings", &self.core.settings)
                    .field("stats", &self.core.stats)
                    .finish_non_exhaustive()
            }
        }
    };
}

common!(ImplicitWorkspace, DenseLinear);
common!(SparseWorkspace, SparseLinear);
