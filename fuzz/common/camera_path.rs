//! What the `camera_path` fuzz target does with one input, shared with the test that
//! replays the committed corpus (crates/scene/tests/fuzz_corpus.rs).

use combustion_scene::{Camera, CameraPath};

/// The camera path parser (`view --camera-path`); every path it accepts gives a finite
/// camera at any time: before, at, between and after its keyframes.
pub fn parse_and_follow(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(path) = CameraPath::parse(text) else {
        return;
    };
    let base = Camera {
        position: glam::Vec3::new(0.0, 0.0, 3.0),
        target: glam::Vec3::ZERO,
        up: glam::Vec3::Y,
        vertical_fov: 0.8,
        near: 0.1,
        far: 100.0,
    };
    let mut times: Vec<f32> = vec![-f32::MAX, -1.0, 0.0, 0.5, 1.0, f32::MAX];
    times.extend(path.times());
    let keys = path.times().collect::<Vec<_>>();
    times.extend(keys.windows(2).map(|w| w[0] + (w[1] - w[0]) * 0.5));
    for time in times {
        let camera = path.at(time, &base);
        assert!(
            camera.position.is_finite() && camera.target.is_finite(),
            "time {time}: {camera:?}"
        );
    }
}
