//! The rasteriser of cloth frames (work in progress).
