//! rapier3d behind the `Engine` trait: the same scene built by `tumble_scenes::build_rapier_with`.

use tumble::scenes::{RapierOptions, RapierWorld, Scene, build_rapier_with};
use tumble_geometry::nalgebra::{Quaternion, Translation3};
use tumble_geometry::{Pose, Rot, Vec3};

use crate::engine::{BodyState, Engine};

/// A rapier3d world loaded with a scene.
pub struct RapierEngine {
    world: RapierWorld,
}

impl RapierEngine {
    /// Builds `scene` with `substeps` solver iterations (rapier's substeps), no sleeping and no
    /// CCD, so that it runs the same discrete, always-awake step Tumble does.
    pub fn new(scene: &Scene, substeps: u32) -> Self {
        let options = RapierOptions {
            solver_iterations: substeps as usize,
            sleep: false,
            ccd: false,
        };
        Self {
            world: build_rapier_with(scene, &options),
        }
    }
}

impl Engine for RapierEngine {
    fn step(&mut self) -> Result<(), String> {
        self.world.step();
        Ok(())
    }

    fn read_states(&self, out: &mut Vec<BodyState>) {
        out.clear();
        let poses = self.world.body_poses();
        let velocities = self.world.body_velocities();
        for ((p, [x, y, z, w]), (v, omega)) in poses.into_iter().zip(velocities) {
            // Rapier keeps its quaternions normalized; `new_unchecked` keeps a NaN visible to
            // the NaN metric instead of normalizing it into something else.
            let rotation = Rot::new_unchecked(Quaternion::new(w, x, y, z));
            out.push(BodyState {
                pose: Pose::from_parts(Translation3::from(Vec3::from(p)), rotation),
                linear_velocity: Vec3::from(v),
                angular_velocity: Vec3::from(omega),
            });
        }
    }
}
