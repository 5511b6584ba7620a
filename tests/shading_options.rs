//! Issue 20 (deliverable 5): one options object. `Renderer::set_shading` builds every
//! pipeline the new `ShadingOptions` need for the scenes it is given before it switches:
//! when a build fails, the options and the frames rendered with them stay as they were;
//! when it succeeds, the next frame needs no `prepare` — for the scene's own frames and
//! for frames lit by a `FrameEnvironment` baked for it. A scene left out of the list
//! still needs `prepare`.
//!
//! The failure is a real one of this renderer's build path: a scene uploaded by another
//! renderer (on the same device) cannot have its pipelines built here
//! (`RenderError::SceneOfAnotherRenderer`). It is listed after a scene of this renderer,
//! so the new options' pipelines for that one are built before the build fails.

use crate::common;

use combustion::renderer::{
    FrameInputs, FresnelModel, Readback, RenderError, Renderer, ShadingOptions,
};
use combustion::scene::{builtin_scene, Environment};

const W: u32 = 64;
const H: u32 = 48;

#[test]
fn a_failed_set_shading_changes_nothing_and_a_successful_one_needs_no_prepare() {
    let readback = Readback::IMAGES;
    let mut headless = common::lavapipe(common::exact_f32());
    let renderer = headless.renderer();
    let spheres = builtin_scene("spheres").expect("built in");
    let gpu = renderer.upload(&spheres).expect("upload");
    let studio = renderer
        .bake_environment(&gpu, &Environment::Studio)
        .expect("bake");
    // A scene of other features, uploaded before the options change and left out of it.
    let left_out = renderer
        .upload(&builtin_scene("gold-copper").expect("built in"))
        .expect("upload");
    let lit = FrameInputs {
        environment: Some(&studio),
        ..FrameInputs::of_scene(&gpu, 1.0)
    };
    let frames = |renderer: &mut Renderer| {
        let own = renderer.render(&gpu, W, H, readback).expect("frame");
        let lit = renderer
            .render_with(&gpu, &lit, W, H, readback)
            .expect("frame lit by the studio");
        (own.hdr, own.ldr, lit.hdr)
    };
    let before = frames(renderer);
    assert_eq!(renderer.shading(), ShadingOptions::default());

    let schlick = ShadingOptions {
        fresnel: FresnelModel::Schlick,
        ..ShadingOptions::default()
    };

    // A failed build: nothing changes.
    let mut other =
        Renderer::new(renderer.device().clone(), common::exact_f32()).expect("renderer");
    let foreign = other.upload(&spheres).expect("upload");
    let built = renderer.stats().pipelines_built;
    let error = renderer
        .set_shading(schlick, &[&gpu, &foreign])
        .unwrap_err();
    assert!(
        matches!(error, RenderError::SceneOfAnotherRenderer),
        "{error}"
    );
    assert!(
        renderer.stats().pipelines_built > built,
        "the listed scene's new pipelines are built before the build fails"
    );
    assert_eq!(renderer.shading(), ShadingOptions::default());
    assert_eq!(renderer.settings().shading, ShadingOptions::default());
    let after_failure = frames(renderer);
    assert!(
        after_failure == before,
        "a failed set_shading changed the frames"
    );
    renderer
        .render(&left_out, W, H, readback)
        .expect("the scene left out renders as before");

    // A successful switch: the next frames need no prepare, lit by the studio or not.
    renderer.set_shading(schlick, &[&gpu]).expect("set_shading");
    assert_eq!(renderer.shading(), schlick);
    assert_eq!(renderer.settings().shading, schlick);
    let built = renderer.stats().pipelines_built;
    let switched = frames(renderer);
    assert_eq!(
        renderer.stats().pipelines_built,
        built,
        "frames build no pipeline"
    );
    assert!(
        switched.0 != before.0,
        "Schlick's Fresnel changes the frame"
    );
    assert!(
        switched.2 != before.2,
        "Schlick's Fresnel changes the frame lit by the studio"
    );
    for (hdr, name) in [(&switched.0, "own"), (&switched.2, "lit")] {
        assert!(
            hdr.iter().flatten().all(|c| c.is_finite()),
            "{name}: non-finite radiance"
        );
    }

    // The scene left out of the list needs prepare (and has it then).
    let error = renderer.render(&left_out, W, H, readback).unwrap_err();
    assert!(matches!(error, RenderError::VariantNotPrepared), "{error}");
    renderer.prepare(&left_out).expect("prepare");
    renderer
        .render(&left_out, W, H, readback)
        .expect("the scene left out, prepared");

    // Back to the defaults: the very frames of before.
    renderer
        .set_shading(ShadingOptions::default(), &[&gpu])
        .expect("set_shading");
    assert!(frames(renderer) == before, "the defaults again");

    drop((foreign, other, left_out, studio, gpu));
    common::finish(headless);
}
