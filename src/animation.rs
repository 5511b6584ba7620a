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
    if let Some(i) = animations
        .iter()
        .position(|a| a.name.as_deref() == Some(asked))
    {
        return Ok(i);
    }
    match asked.parse::<usize>() {
        Ok(i) if i < animations.len() => Ok(i),
        _ => Err(Error::Usage(format!(
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
    Ok(scene.pose_at(index, time.unwrap_or(0.0)))
}
