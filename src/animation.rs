//! Choosing a scene's animation and time from the command line (`render`, `bench`,
//! `view`): the pose a frame shows, made by the scene crate's player.

use combustion_scene::{ObjectPoses, Scene};

use crate::Error;

/// The index of the animation `asked` names in `scene` (its name, else its index from
/// 0); the first without one. An error names the scene's animations when none matches,
/// or says the scene has none.
pub fn choose_animation(scene: &Scene, asked: Option<&str>) -> Result<usize, Error> {
    let animations = &scene.motion.animations;
    let names = || {
        animations
            .iter()
            .enumerate()
            .map(|(i, a)| match &a.name {
                Some(name) => format!("{i} `{name}`"),
                None => i.to_string(),
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    if animations.is_empty() {
        return Err(Error::Usage(format!(
            "{}: the scene has no animations (--time and --animation need one)",
            scene.name
        )));
    }
    let Some(asked) = asked else { return Ok(0) };
    let named = animations
        .iter()
        .position(|a| a.name.as_deref() == Some(asked));
    let indexed = asked
        .parse::<usize>()
        .ok()
        .filter(|&i| i < animations.len());
    match (named, indexed) {
        // A number that is both an index and another animation's name: said, not
        // chosen (an index 0 quietly lost to an animation named "0").
        (Some(n), Some(i)) if n != i => Err(Error::Usage(format!(
            "--animation {asked}: both animation {i} and animation {n}, named `{asked}`; the scene's animations are {}: give another name or the index of the other",
            names()
        ))),
        (Some(i), _) | (None, Some(i)) => Ok(i),
        (None, None) => Err(Error::Usage(format!(
            "--animation {asked}: the scene has no such animation (it has {})",
            names()
        ))),
    }
}

/// The pose of `scene` at `time` seconds of the animation `animation` names (the
/// first without a name; time 0 without a time), or `None` when neither is given (the
/// scene as it is, at rest).
pub fn pose_at(
    scene: &Scene,
    animation: Option<&str>,
    time: Option<f32>,
) -> Result<Option<ObjectPoses>, Error> {
    if animation.is_none() && time.is_none() {
        return Ok(None);
    }
    let index = choose_animation(scene, animation)?;
    sampled_pose(scene, index, time.unwrap_or(0.0)).map(Some)
}

/// The pose of `scene` at `time` seconds of its animation `index`, checked as it is
/// sampled: a transform, morph weight or joint matrix that is not a finite number (keys
/// that interpolate to no rotation, as a rotation from q to −q or keys of zeros do) is
/// refused naming the scene, the animation and the time — the renderer would refuse the
/// pose naming neither.
pub fn sampled_pose(scene: &Scene, index: usize, time: f32) -> Result<ObjectPoses, Error> {
    let which = || match scene
        .motion
        .animations
        .get(index)
        .and_then(|a| a.name.as_ref())
    {
        Some(name) => format!("animation {index} `{}`", combustion_optics::shortened(name)),
        None => format!("animation {index}"),
    };
    let Some(pose) = scene.pose_at(index, time) else {
        return Err(Error::Usage(format!("{}: no {}", scene.name, which())));
    };
    let not_finite = |m: &glam::Mat4| !m.is_finite();
    let problem = pose
        .transforms
        .iter()
        .position(not_finite)
        .map(|i| format!("object {i}'s transform"))
        .or_else(|| {
            let weights = pose.weights.iter();
            weights
                .enumerate()
                .find(|(_, w)| w.iter().any(|x| !x.is_finite()))
                .map(|(i, _)| format!("object {i}'s morph weights"))
        })
        .or_else(|| {
            let skins = pose.joints.iter();
            skins
                .enumerate()
                .find(|(_, joints)| joints.iter().any(not_finite))
                .map(|(s, _)| format!("skin {s}'s joint matrices"))
        });
    match problem {
        Some(what) => Err(Error::Animation(format!(
            "{}: {} at {} s gives {what} values that are not finite numbers (its keys interpolate to nothing there: a rotation from q to −q, or keys of zeros); nothing rendered",
            scene.name,
            which(),
            combustion_optics::readable(time)
        ))),
        None => Ok(pose),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rotation keyed by zeros (no rotation at all) is refused as it is sampled,
    /// naming the scene, the animation and the time; a proper one samples.
    #[test]
    fn a_pose_that_is_not_finite_names_scene_animation_and_time() {
        use combustion_scene::motion::{
            Animation, Channel, Interpolation, LocalTransform, Node, Property, Sampler,
        };
        let mut scene = combustion_scene::builtin_scene("spheres").unwrap();
        scene.motion.nodes = vec![Node {
            name: None,
            parent: None,
            local: LocalTransform::IDENTITY,
            skin: None,
            weights: Vec::new(),
        }];
        scene.objects[0].node = Some(combustion_scene::NodeLink {
            node: 0,
            offset: glam::Mat4::IDENTITY,
        });
        let rotation = |values: Vec<f32>| Animation {
            name: Some("spin".into()),
            samplers: vec![Sampler {
                interpolation: Interpolation::Linear,
                times: vec![0.0, 1.0],
                values,
            }],
            channels: vec![Channel {
                node: 0,
                property: Property::Rotation,
                sampler: 0,
            }],
        };
        scene.motion.animations = vec![rotation(vec![0.0; 8])];
        let message = pose_at(&scene, None, Some(0.5)).unwrap_err().to_string();
        assert!(
            message.contains(
                "animation 0 `spin` at 0.5 s gives object 0's transform values that are not finite"
            ),
            "{message}"
        );
        scene.motion.animations = vec![rotation(vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0])];
        assert!(pose_at(&scene, None, Some(0.5)).unwrap().is_some());
    }

    fn with_animations(names: &[Option<&str>]) -> Scene {
        let mut scene = combustion_scene::builtin_scene("spheres").unwrap();
        scene.motion.animations = names
            .iter()
            .map(|name| combustion_scene::motion::Animation {
                name: name.map(str::to_owned),
                samplers: Vec::new(),
                channels: Vec::new(),
            })
            .collect();
        scene
    }

    /// A name or an index chooses an animation; a number that is both an index and
    /// another animation's name is refused naming both (an index 0 quietly lost to an
    /// animation named "0").
    #[test]
    fn a_number_that_is_an_index_and_another_name_is_refused() {
        let scene = with_animations(&[Some("walk"), Some("0")]);
        assert_eq!(choose_animation(&scene, Some("walk")).unwrap(), 0);
        assert_eq!(choose_animation(&scene, Some("1")).unwrap(), 1);
        let message = choose_animation(&scene, Some("0")).unwrap_err().to_string();
        assert!(
            message.contains("--animation 0: both animation 0 and animation 1, named `0`"),
            "{message}"
        );
        let same = with_animations(&[Some("0"), None]);
        assert_eq!(choose_animation(&same, Some("0")).unwrap(), 0);
        assert!(choose_animation(&same, Some("2")).is_err());
    }
}
