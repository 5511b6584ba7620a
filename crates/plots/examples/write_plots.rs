//! Writes the example plots: `cargo run -p combustion-plots --example write_plots -- [DIR]`
//! (default directory `/tmp/plots`).

use combustion_plots::{
    plot_dielectric_family, plot_reflectance, plot_spectrum, BuiltinMetal, PlotError, PlotMaterial,
    ReflectancePlot, FIGURE_12_ETAS,
};
use std::path::{Path, PathBuf};

fn main() {
    let dir = std::env::args_os()
        .nth(1)
        .map_or_else(|| PathBuf::from("/tmp/plots"), PathBuf::from);
    if let Err(error) = write_all(&dir) {
        eprintln!("error: {error}");
        std::process::exit(1);
    }
}

fn write_all(dir: &Path) -> Result<(), Box<dyn std::error::Error>> {
    std::fs::create_dir_all(dir)?;
    let save = |name: &str, png: Result<combustion_plots::Png, PlotError>| {
        let path = dir.join(name);
        png?.save(&path)?;
        println!("{}", path.display());
        Ok::<(), Box<dyn std::error::Error>>(())
    };
    for metal in [BuiltinMetal::Gold, BuiltinMetal::Copper] {
        save(
            &format!("{}_reflectance.png", metal.name()),
            plot_reflectance(&ReflectancePlot::new(PlotMaterial::Metal(metal))),
        )?;
        save(
            &format!("{}_reflectance_in_water.png", metal.name()),
            plot_reflectance(&ReflectancePlot {
                outside_eta: 1.33,
                ..ReflectancePlot::new(PlotMaterial::Metal(metal))
            }),
        )?;
        save(
            &format!("{}_spectrum.png", metal.name()),
            plot_spectrum(
                &format!("{} ({}, {})", metal.name(), metal.symbol(), metal.dataset()),
                metal.spectrum(),
                800,
                500,
            ),
        )?;
    }
    let glass = PlotMaterial::Dielectric { eta: 1.5 };
    save(
        "glass_from_air.png",
        plot_reflectance(&ReflectancePlot::new(glass.clone())),
    )?;
    save(
        "glass_from_water.png",
        plot_reflectance(&ReflectancePlot {
            outside_eta: 1.33,
            ..ReflectancePlot::new(glass)
        }),
    )?;
    save(
        "water_to_air.png",
        plot_reflectance(&ReflectancePlot {
            outside_eta: 1.33,
            ..ReflectancePlot::new(PlotMaterial::Dielectric { eta: 1.0 })
        }),
    )?;
    save(
        "dielectric_family.png",
        plot_dielectric_family(&FIGURE_12_ETAS, 1.0, 800, 500),
    )?;
    save(
        "dielectric_family_from_water.png",
        plot_dielectric_family(&[1.0, 1.2, 1.5, 2.0], 1.33, 800, 500),
    )?;
    Ok(())
}
