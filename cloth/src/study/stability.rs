//! The largest stable step of a method on a scene (work in progress).
