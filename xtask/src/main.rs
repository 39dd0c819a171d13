//! Project tasks: `cargo xtask validate`, `cargo xtask bench`, `cargo xtask tidy`.
#![warn(missing_docs)]
#![allow(dead_code)]

mod energy;
mod engine;
mod grid;
mod metrics;
mod penetration;
mod run;
mod scene_info;
mod timing;

fn main() {}
