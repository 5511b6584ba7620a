//! The report's G-buffer storage section: each storage the renderer offers
//! ([`GBufferStorage`]: base colour in 8- or 16-bit sRGB or linear f16; normal,
//! roughness and anisotropy in 16 or 8 bits) on each scene without an environment, its
//! cost (the G-buffer and lighting passes and the frame, GPU medians) against its error
//! end to end (the frame against the scene's f64 reference, `crate::end_to_end`, and
//! the storage's share of it). Written as `gbuffer-storage.csv` and a section of
//! `report.md`; docs/gbuffer.md chooses the default by it.

use std::fmt::Write as _;

use combustion_reference::SceneBvh;
use combustion_renderer::{
    BaseColorStorage, GBufferStorage, PassTimings, Readback, RendererSettings, SurfaceStorage,
};

use super::{md_cell, time_frames, PassSpreads, ReportDesc, Spread};
use crate::end_to_end::{precision_of, EndToEndErrors, SceneReference};
use crate::{check_validation, Error};

/// Every storage, the default first.
pub fn all_storages() -> Vec<GBufferStorage> {
    let mut all = Vec::new();
    for surface in SurfaceStorage::ALL {
        for base_color in BaseColorStorage::ALL {
            all.push(GBufferStorage {
                base_color,
                surface,
            });
        }
    }
    all
}

/// One scene and storage.
#[derive(Clone, Debug, PartialEq)]
pub struct StorageRow {
    /// The scene's label.
    pub scene: String,
    /// The storage.
    pub storage: GBufferStorage,
    /// The G-buffer pass's GPU time.
    pub gbuffer: Spread,
    /// The lighting pass's GPU time.
    pub lighting: Spread,
    /// The whole frame's GPU time.
    pub total: Spread,
    /// The frame against the scene's reference stored this way.
    pub errors: EndToEndErrors,
}

/// Measures every storage of `desc.storages` on every scene of `scenes` without an
/// environment (one renderer per scene and storage: a renderer's storage is fixed);
/// `progress(what)` before each.
pub(super) fn measure(
    scenes: &[(String, combustion_scene::Scene)],
    desc: &ReportDesc,
    threads: usize,
    mut progress: impl FnMut(&str),
) -> Result<Vec<StorageRow>, Error> {
    let mut rows = Vec::new();
    for (label, scene) in scenes {
        if scene.environment.is_some() {
            continue;
        }
        let bvh = SceneBvh::new(scene);
        let mut reference: Option<SceneReference> = None;
        for &storage in &desc.storages {
            progress(&format!("{label} G-buffer {}", storage.name()));
            let precision = precision_of(storage);
            let reference = match reference.take() {
                Some(mut r) => {
                    r.store_as(precision, threads);
                    reference.insert(r)
                }
                None => reference.insert(SceneReference::new(
                    scene,
                    &bvh,
                    &scene.lights,
                    (desc.width, desc.height),
                    precision,
                    threads,
                )),
            };
            let mut headless = desc.headless(RendererSettings {
                gbuffer: storage,
                ..RendererSettings::default()
            })?;
            let renderer = headless.renderer();
            let gpu = renderer.upload(scene)?;
            let frame = renderer.render(&gpu, desc.width, desc.height, Readback::ALL)?;
            let errors = reference.compare(&frame).summary();
            let timings = time_frames(renderer, &gpu, desc.width, desc.height, desc.frames)?;
            let passes = PassSpreads::of(&timings);
            rows.push(StorageRow {
                scene: label.clone(),
                storage,
                gbuffer: passes.get(PassTimings::GBUFFER),
                lighting: passes.get(PassTimings::LIGHTING),
                total: Spread::of(timings.iter().map(|t| t.total_ms).collect()),
                errors,
            });
            renderer.retire(gpu);
            let validation = headless.validation_log();
            drop(headless);
            check_validation(&validation)?;
        }
    }
    Ok(rows)
}

/// `gbuffer-storage.csv`: one row per scene and storage.
pub fn csv(rows: &[StorageRow]) -> String {
    let mut table = combustion_report_csv::Table::new(&[
        "scene",
        "gbuffer_storage",
        "bytes_per_pixel",
        "gbuffer_ms",
        "lighting_ms",
        "total_ms",
        "pixels_compared",
        "error_mean",
        "error_max",
        "storage_share_mean",
        "storage_share_max",
        "rest_mean",
        "rest_max",
    ]);
    for r in rows {
        let e = &r.errors;
        table.row([
            r.scene.clone(),
            r.storage.name().to_string(),
            r.storage.bytes_per_pixel().to_string(),
            format!("{:.3}", r.gbuffer.median),
            format!("{:.3}", r.lighting.median),
            format!("{:.3}", r.total.median),
            e.compared.to_string(),
            format!("{:.3e}", e.total.mean),
            format!("{:.3e}", e.total.max),
            format!("{:.3e}", e.storage.mean),
            format!("{:.3e}", e.storage.max),
            format!("{:.3e}", e.rest.mean),
            format!("{:.3e}", e.rest.max),
        ]);
    }
    table.finish()
}

/// Per storage over the scenes: mean G-buffer, lighting and frame times, and the mean
/// of the scenes' mean errors and storage shares, the default first.
pub fn per_storage(rows: &[StorageRow]) -> Vec<(GBufferStorage, [f64; 5])> {
    let mut storages: Vec<GBufferStorage> = Vec::new();
    for r in rows {
        if !storages.contains(&r.storage) {
            storages.push(r.storage);
        }
    }
    storages
        .into_iter()
        .map(|storage| {
            let of: Vec<&StorageRow> = rows.iter().filter(|r| r.storage == storage).collect();
            let mean = |f: &dyn Fn(&StorageRow) -> f64| {
                of.iter().map(|r| f(r)).sum::<f64>() / of.len().max(1) as f64
            };
            (
                storage,
                [
                    mean(&|r| r.gbuffer.median),
                    mean(&|r| r.lighting.median),
                    mean(&|r| r.total.median),
                    mean(&|r| r.errors.total.mean),
                    mean(&|r| r.errors.storage.mean),
                ],
            )
        })
        .collect()
}

/// The report's G-buffer storage section (empty without rows).
pub fn markdown(rows: &[StorageRow]) -> String {
    if rows.is_empty() {
        return String::new();
    }
    let mut out = String::from(
        "## G-buffer storage (scenes without an environment)\n\nEach storage of the G-buffer (base colour + metalness: `srgb8` 8-bit unorm through the sRGB curve, `srgb16` 16-bit, `f16` linear half float; normal, roughness, anisotropy: `unorm16` or `unorm8`), default shading options, one renderer each. Times: GPU medians. Errors: the frame against the scene's f64 reference (end to end, edges left out), relative; *storage*: the share the reference itself predicts from the formats (the exact inputs against the inputs as stored); *rest*: the GPU against the reference stored the same way.\n\n| scene | storage | bytes/pixel | G-buffer ms | lighting ms | frame ms | error mean / max | storage mean | rest mean / max |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let e = &r.errors;
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:.2} | {:.2} | {:.2} | {:.2e} / {:.2e} | {:.2e} | {:.2e} / {:.2e} |",
            md_cell(&r.scene),
            r.storage.name(),
            r.storage.bytes_per_pixel(),
            r.gbuffer.median,
            r.lighting.median,
            r.total.median,
            e.total.mean,
            e.total.max,
            e.storage.mean,
            e.rest.mean,
            e.rest.max,
        );
    }
    out += "\nPer storage over the scenes (means):\n\n| storage | bytes/pixel | G-buffer ms | lighting ms | frame ms | error mean | storage mean |\n|---|---|---|---|---|---|---|\n";
    for (storage, [g, l, t, e, s]) in per_storage(rows) {
        let _ = writeln!(
            out,
            "| {} | {} | {g:.2} | {l:.2} | {t:.2} | {e:.2e} | {s:.2e} |",
            storage.name(),
            storage.bytes_per_pixel(),
        );
    }
    out + "\n"
}
