//! What the viewer's keys change besides the camera: which scene is shown, and the
//! toggles applied to it — the Fresnel model, a diffuse model for every material, the
//! outside medium, the exposure. Pure data; the viewer turns changes into uploads and
//! scene edits between frames.

use std::path::PathBuf;
use std::time::{Instant, SystemTime};

use combustion_renderer::{FresnelModel, ShadowFilter, ShadowSettings};
use combustion_scene::{DiffuseModel, Scene};

use crate::SceneSource;

/// Overrides applied on top of the scene as loaded.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Overrides {
    /// Every material's diffuse model (`None`: each its own).
    pub diffuse: Option<DiffuseModel>,
    /// The outside medium's index for the scene and every material (`None`: as loaded).
    pub medium: Option<f32>,
}

impl Overrides {
    /// The next diffuse override: as loaded → Lambert → Oren–Nayar qualitative → full.
    pub fn cycle_diffuse(&mut self) {
        self.diffuse = match self.diffuse {
            None => Some(DiffuseModel::Lambert),
            Some(DiffuseModel::Lambert) => Some(DiffuseModel::OrenNayarQualitative),
            Some(DiffuseModel::OrenNayarQualitative) => Some(DiffuseModel::OrenNayarFull),
            Some(DiffuseModel::OrenNayarFull) => None,
        };
    }

    /// The next outside medium: as loaded → air (1.0) → water (1.33).
    pub fn cycle_medium(&mut self) {
        self.medium = match self.medium {
            None => Some(1.0),
            Some(1.0) => Some(WATER_IOR),
            Some(_) => None,
        };
    }

    /// `scene` with these overrides.
    pub fn apply(&self, scene: &Scene) -> Scene {
        let mut out = scene.clone();
        if let Some(model) = self.diffuse {
            for m in &mut out.materials {
                m.diffuse_model = model;
            }
        }
        if let Some(ior) = self.medium {
            out.outside_ior = ior;
            for m in &mut out.materials {
                m.outside_ior = None;
            }
        }
        out
    }

    /// A short description, for the title.
    pub fn describe(&self) -> String {
        let diffuse = match self.diffuse {
            None => "as loaded",
            Some(DiffuseModel::Lambert) => "Lambert",
            Some(DiffuseModel::OrenNayarQualitative) => "Oren–Nayar qualitative",
            Some(DiffuseModel::OrenNayarFull) => "Oren–Nayar full",
        };
        let medium = match self.medium {
            None => "as loaded".to_owned(),
            Some(1.0) => "air".to_owned(),
            Some(m) => format!("η {m}"),
        };
        format!("diffuse {diffuse}, medium {medium}")
    }
}

/// Water's index of refraction, the outside medium the `O` key offers after air.
pub const WATER_IOR: f32 = 1.33;

/// Exposure steps of the `+` and `-` keys: half a stop.
pub const EXPOSURE_STEP: f32 = std::f32::consts::SQRT_2;

/// The next Fresnel model (full → Schlick → F82 → full; the last two are comparison
/// variants).
pub fn toggle_fresnel(model: FresnelModel) -> FresnelModel {
    match model {
        FresnelModel::Full => FresnelModel::Schlick,
        FresnelModel::Schlick => FresnelModel::F82,
        FresnelModel::F82 => FresnelModel::Full,
    }
}

/// Shadows on (the default settings) or off, the `K` key.
pub fn toggle_shadows(shadows: Option<ShadowSettings>) -> Option<ShadowSettings> {
    match shadows {
        Some(_) => None,
        None => Some(ShadowSettings::DEFAULT),
    }
}

/// The environment's occlusion, the `B` key: none → the screen-space pass
/// (`ambient-occlusion`) → the ray-traced pass (`ray-traced-occlusion`, on a device with
/// ray queries) → none; the other optional passes kept.
pub fn cycle_occlusion(
    passes: combustion_renderer::OptionalPasses,
    ray_queries: bool,
) -> combustion_renderer::OptionalPasses {
    let (Some(screen), Some(traced)) = (
        combustion_renderer::optional_pass("ambient-occlusion"),
        combustion_renderer::optional_pass("ray-traced-occlusion"),
    ) else {
        return passes;
    };
    let next = if passes.contains(traced) {
        None
    } else if passes.contains(screen) {
        ray_queries.then_some(traced)
    } else {
        Some(screen)
    };
    [screen, traced].into_iter().fold(passes, |set, pass| {
        set.with(pass, next.is_some_and(|n| n.name == pass.name))
    })
}

/// The next shadow filter ([`ShadowFilter::ALL`] in order), the `L` key; shadows on if
/// they were off.
pub fn cycle_shadow_filter(shadows: Option<ShadowSettings>) -> Option<ShadowSettings> {
    let settings = shadows.unwrap_or_default();
    let i = ShadowFilter::ALL
        .iter()
        .position(|&f| f == settings.filter)
        .unwrap_or(0);
    Some(ShadowSettings {
        filter: ShadowFilter::ALL[(i + 1) % ShadowFilter::ALL.len()],
        ..settings
    })
}

/// The built-in scene on number key `n` (1 … 9 the first nine, 0 the tenth), if any.
pub fn builtin_on_key(n: u32) -> Option<SceneSource> {
    let names = combustion_scene::BUILTIN_SCENES;
    let index = usize::try_from(if n == 0 { 9 } else { n - 1 }).ok()?;
    names
        .get(index)
        .map(|name| SceneSource::Builtin((*name).to_owned()))
}

/// A scene's animation as the viewer plays it: which one, where in it, how fast, and
/// whether it plays (Space), in the scene's own seconds; looping.
#[derive(Clone, Copy, Debug)]
pub struct Playback {
    /// The animation (index into the scene's).
    pub animation: usize,
    /// Where in it, seconds.
    pub time: f32,
    /// Its seconds per wall-clock second.
    pub speed: f32,
    /// Whether it advances.
    pub playing: bool,
    last: Instant,
}

/// Playback speeds the [ and ] keys step between (halving, doubling).
const SPEEDS: (f32, f32) = (1.0 / 16.0, 16.0);
/// How far , and . move the animation, seconds of its time.
pub const SCRUB_STEP: f32 = 0.1;

impl Playback {
    /// The first animation from its start, playing at its own speed.
    pub fn new() -> Self {
        Self {
            animation: 0,
            time: 0.0,
            speed: 1.0,
            playing: true,
            last: Instant::now(),
        }
    }

    /// Advances the clock to now (if playing) and returns the pose of `scene` there,
    /// `None` for a scene without animations.
    pub fn pose(&mut self, scene: &Scene) -> Option<combustion_scene::ObjectPoses> {
        let now = Instant::now();
        let elapsed = (now - self.last).as_secs_f32();
        self.last = now;
        let animation = scene.motion.animations.get(self.animation)?;
        if self.playing {
            self.time += elapsed * self.speed;
        }
        self.time = match animation.duration() {
            d if d > 0.0 => self.time.rem_euclid(d),
            _ => 0.0,
        };
        self.current_pose(scene)
    }

    /// The pose of `scene` where the clock stands (not advancing it).
    pub fn current_pose(&self, scene: &Scene) -> Option<combustion_scene::ObjectPoses> {
        scene.pose_at(self.animation, self.time)
    }

    /// The next of `count` animations, from its start.
    pub fn next_animation(&mut self, count: usize) {
        if count > 0 {
            self.animation = (self.animation + 1) % count;
            self.time = 0.0;
        }
    }

    /// Half or twice the speed (`faster`), within 1/16 and 16.
    pub fn change_speed(&mut self, faster: bool) {
        let factor = if faster { 2.0 } else { 0.5 };
        self.speed = (self.speed * factor).clamp(SPEEDS.0, SPEEDS.1);
    }

    /// The animation described for the statistics panel (`None` without one).
    pub fn describe(&self, scene: &Scene) -> Option<String> {
        let animation = scene.motion.animations.get(self.animation)?;
        Some(format!(
            "animation {} of {}{} · {:.2} / {:.2} s · ×{} · {}",
            self.animation + 1,
            scene.motion.animations.len(),
            animation
                .name
                .as_deref()
                .map_or(String::new(), |n| format!(" `{n}`")),
            self.time,
            animation.duration(),
            self.speed,
            if self.playing { "playing" } else { "paused" }
        ))
    }
}

impl Default for Playback {
    fn default() -> Self {
        Self::new()
    }
}

/// When a scene file last changed (`None` for built-in scenes or unreadable files).
pub fn modified(source: &SceneSource) -> Option<SystemTime> {
    match source {
        SceneSource::Builtin(_) => None,
        SceneSource::File(path) => std::fs::metadata(path).and_then(|m| m.modified()).ok(),
    }
}

/// A file dropped on the window, as a scene source.
pub fn dropped(path: PathBuf) -> SceneSource {
    SceneSource::File(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_occlusion_key_cycles_none_screen_space_and_ray_traced() {
        let none = combustion_renderer::OptionalPasses::NONE;
        let names =
            |p: combustion_renderer::OptionalPasses| p.iter().map(|p| p.name).collect::<Vec<_>>();
        let screen = cycle_occlusion(none, true);
        assert_eq!(names(screen), ["ambient-occlusion"]);
        let traced = cycle_occlusion(screen, true);
        assert_eq!(names(traced), ["ray-traced-occlusion"]);
        assert_eq!(cycle_occlusion(traced, true), none);
        assert_eq!(
            cycle_occlusion(screen, false),
            none,
            "no ray queries: back to none"
        );
    }

    #[test]
    fn shadow_keys_toggle_and_cycle_every_filter() {
        assert_eq!(toggle_shadows(None), Some(ShadowSettings::DEFAULT));
        assert_eq!(toggle_shadows(Some(ShadowSettings::DEFAULT)), None);
        let mut shadows = None;
        let mut seen = Vec::new();
        for _ in 0..ShadowFilter::ALL.len() {
            shadows = cycle_shadow_filter(shadows);
            seen.push(shadows.unwrap().filter);
        }
        for filter in ShadowFilter::ALL {
            assert!(seen.contains(&filter), "{filter:?} never reached");
        }
    }

    #[test]
    fn overrides_cycle_and_apply_to_every_material() {
        let scene = combustion_scene::builtin_scene("diffuse-models").unwrap();
        let mut o = Overrides::default();
        let same = o.apply(&scene);
        assert_eq!(same.materials, scene.materials);
        assert_eq!(same.outside_ior, scene.outside_ior);
        o.cycle_diffuse();
        o.cycle_diffuse();
        assert_eq!(o.diffuse, Some(DiffuseModel::OrenNayarQualitative));
        o.cycle_medium();
        o.cycle_medium();
        assert_eq!(o.medium, Some(WATER_IOR));
        let applied = o.apply(&scene);
        assert!(applied
            .materials
            .iter()
            .all(|m| m.diffuse_model == DiffuseModel::OrenNayarQualitative
                && m.outside_ior.is_none()));
        assert_eq!(applied.outside_ior, WATER_IOR);
        assert_eq!(applied.meshes, scene.meshes, "geometry is untouched");
        o.cycle_diffuse();
        o.cycle_diffuse();
        o.cycle_medium();
        assert_eq!(
            o,
            Overrides::default(),
            "both cycles come back to the scene's own"
        );
    }

    #[test]
    fn number_keys_name_the_builtin_scenes() {
        assert_eq!(
            builtin_on_key(1),
            Some(SceneSource::Builtin("spheres".into()))
        );
        assert_eq!(
            builtin_on_key(0),
            Some(SceneSource::Builtin(
                combustion_scene::BUILTIN_SCENES[9].into()
            ))
        );
        assert_eq!(builtin_on_key(99), None);
        assert_eq!(
            toggle_fresnel(toggle_fresnel(toggle_fresnel(FresnelModel::Full))),
            FresnelModel::Full
        );
    }
}

#[cfg(test)]
mod playback_tests {
    use super::*;
    use combustion_scene::motion::{
        Animation, Channel, Interpolation, LocalTransform, Node, Property, Sampler,
    };

    /// The clock loops over the animation's 2 s (also when scrubbed back past 0), the
    /// speed stays between 1/16 and 16, N cycles the animations.
    #[test]
    fn the_clock_loops_and_the_speed_is_bounded() {
        let mut scene = combustion_scene::builtin_scene("spheres").unwrap();
        scene.motion.nodes.push(Node {
            name: None,
            parent: None,
            local: LocalTransform::IDENTITY,
            skin: None,
            weights: Vec::new(),
        });
        scene.motion.animations.push(Animation {
            name: Some("two seconds".into()),
            samplers: vec![Sampler {
                interpolation: Interpolation::Linear,
                times: vec![0.0, 2.0],
                values: vec![0.0; 6],
            }],
            channels: vec![Channel {
                node: 0,
                property: Property::Translation,
                sampler: 0,
            }],
        });
        let mut playback = Playback::new();
        playback.playing = false;
        playback.time = 5.5;
        assert!(playback.pose(&scene).is_some());
        assert_eq!(playback.time, 1.5);
        playback.time -= 1.75;
        playback.pose(&scene);
        assert_eq!(playback.time, 1.75);
        for _ in 0..10 {
            playback.change_speed(true);
        }
        assert_eq!(playback.speed, 16.0);
        for _ in 0..20 {
            playback.change_speed(false);
        }
        assert_eq!(playback.speed, 1.0 / 16.0);
        for _ in 0..3 {
            playback.next_animation(3);
        }
        assert_eq!((playback.animation, playback.time), (0, 0.0));
        let described = playback.describe(&scene).unwrap();
        assert!(
            described.contains("`two seconds`") && described.contains("paused"),
            "{described}"
        );
    }
}
