//! `combustion eval` (any term of the f64 optics reference as JSON) and `combustion plot`.

use std::path::Path;

use combustion::spectra::Spectrum;
use combustion::{output, Error};
use combustion_plots::{PlotMaterial, ReflectancePlot, FIGURE_12_ETAS};

use super::*;
use super::{write_stdout, CliError};

/// Reads a `wavelength_nm,n,k` table; problems name the file and the line.
pub(crate) fn read_spectrum(path: &Path) -> Result<Spectrum, CliError> {
    let text =
        combustion::input::read_text(path, combustion::input::MAX_TABLE_BYTES, "a spectral table")
            .map_err(|e| CliError::Failed(format!("cannot read {}: {e}", path.display())))?;
    Spectrum::from_csv(&text).map_err(|e| CliError::Failed(format!("{}: {e}", path.display())))
}

/// The file name of `path` without its folder, for a plot's title.
pub(crate) fn file_label(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

pub(crate) fn write_plot(path: &Path, png: &combustion_plots::Png) -> Result<(), CliError> {
    output::write_file_atomically(path, &png.bytes)?;
    outln!("wrote {} ({}x{})", path.display(), png.width, png.height);
    Ok(())
}

pub(crate) fn eval(o: &EvalArgs) -> Result<(), Error> {
    if o.list {
        for (name, what) in combustion::eval::TERMS {
            outln!("{name:<24} {what}");
        }
        return Ok(());
    }
    // clap requires TERM without --list.
    let term = o.term.as_deref().unwrap_or_default();
    outln!("{}", combustion::eval::evaluate(term, &o.inputs)?);
    Ok(())
}

pub(crate) fn plot(command: &PlotCommand) -> Result<(), CliError> {
    match command {
        PlotCommand::Reflectance(a) => {
            let (width, height) = a.image.size((800, 500));
            let path = a.image.output("reflectance")?;
            // clap's group admits exactly one material.
            let material = if let Some(metal) = a.metal {
                PlotMaterial::Metal(metal)
            } else if let Some(eta) = a.dielectric {
                PlotMaterial::Dielectric { eta }
            } else if let Some(eta) = a.eta {
                PlotMaterial::Conductor {
                    eta,
                    k: a.k.unwrap_or([0.0; 3]),
                }
            } else {
                let file = a.csv.as_deref().unwrap_or(Path::new(""));
                PlotMaterial::Spectral {
                    name: file_label(file),
                    spectrum: read_spectrum(file)?,
                }
            };
            let png = combustion_plots::plot_reflectance(&ReflectancePlot {
                material,
                outside_eta: a.outside_ior,
                polarisation_weight: a.polarisation,
                width,
                height,
            })?;
            write_plot(&path, &png)
        }
        PlotCommand::Spectrum(a) => {
            let (width, height) = a.image.size((800, 600));
            let path = a.image.output("spectrum")?;
            // clap's group admits exactly one of --metal and --csv.
            let (name, spectrum) = match (a.metal, &a.csv) {
                (Some(metal), _) => (
                    format!("{} ({}, {})", metal.name(), metal.symbol(), metal.dataset()),
                    metal.spectrum().clone(),
                ),
                (None, file) => {
                    let file = file.as_deref().unwrap_or(Path::new(""));
                    (file_label(file), read_spectrum(file)?)
                }
            };
            let png = combustion_plots::plot_spectrum(&name, &spectrum, width, height)?;
            write_plot(&path, &png)
        }
        PlotCommand::Dielectrics(a) => {
            // How many is the plot's to judge (at least one, at most MAX_FAMILY).
            let etas = a
                .etas
                .as_ref()
                .map_or_else(|| FIGURE_12_ETAS.to_vec(), |e| e.0.clone());
            let (width, height) = a.image.size((800, 500));
            let path = a.image.output("dielectrics")?;
            let png =
                combustion_plots::plot_dielectric_family(&etas, a.outside_ior, width, height)?;
            write_plot(&path, &png)
        }
    }
}
