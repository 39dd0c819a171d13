//! The narrow phase's specification: an exact `f64` reference of box-box contact geometry, the
//! documented feature-choice rules evaluated on it, a seeded random property test over box
//! pairs around touching, and targeted tests of what random pairs do not pin down (exact ties,
//! hysteresis, id packing, tolerance values, frame mapping, the margin cutoff).

mod random_pairs;
mod reference;
mod spec;
mod targeted;
