//! `tumble_scenes::Scene::from_json` on arbitrary bytes (those that are UTF-8).
//!
//! Checked: no panic; an accepted scene saves to JSON and loads back equal; it builds a world
//! (`World::from_scene` on the CPU backend), since a scene that passed its own validation must
//! not then be refused by the engine (the scene applies the world's bounds when it is read);
//! the world steps three times without panic, and every pose and velocity stays finite (known
//! finding `nonfinite`).
//! See `tumble_fuzz::skipped` for letting a recorded finding through.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tumble::{World, WorldConfig};
use tumble_fuzz::skipped;
use tumble_scenes::Scene;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(scene) = Scene::from_json(text) else {
        return;
    };
    let saved = scene.to_json();
    match Scene::from_json(&saved) {
        Ok(loaded) => assert_eq!(loaded, scene, "the saved scene loads back different"),
        Err(e) => panic!("the saved scene does not load back: {e}\n{saved}"),
    }
    let (mut world, handles) = match World::from_scene(&scene, WorldConfig::default()) {
        Ok(built) => built,
        Err(e) => panic!("an accepted scene is refused by the world: {e}\n{saved}"),
    };
    assert_eq!(handles.len(), scene.bodies.len());
    for _ in 0..3 {
        world.step().expect("a CPU step of a built world");
    }
    if skipped("nonfinite") {
        return;
    }
    for &h in &handles {
        let pose = world.pose(h).expect("live handle");
        let v = world.linear_velocity(h).expect("live handle");
        let w = world.angular_velocity(h).expect("live handle");
        let finite = pose.translation.vector.iter().all(|c| c.is_finite())
            && pose.rotation.coords.iter().all(|c| c.is_finite())
            && v.iter().chain(w.iter()).all(|c| c.is_finite());
        assert!(
            finite,
            "non-finite state {pose:?} {v:?} {w:?} after 3 steps of\n{saved}"
        );
    }
});
