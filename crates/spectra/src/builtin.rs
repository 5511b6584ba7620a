//! The built-in measured tables, embedded from `assets/spectra/` at compile time.

use crate::Spectrum;
use std::sync::OnceLock;

macro_rules! asset {
    ($file:literal) => {
        include_str!(concat!("../../../assets/spectra/", $file))
    };
}

macro_rules! database {
    () => {
        "refractiveindex.info-database (M. N. Polyanskiy, Sci. Data 11, 94 (2024), \
         doi:10.1038/s41597-023-02898-2), CC0 1.0"
    };
}

/// `measurement; database, database/data/main/<path>`.
macro_rules! citation {
    ($measurement:expr, $path:literal) => {
        concat!(
            $measurement,
            "; ",
            database!(),
            ", database/data/main/",
            $path
        )
    };
}

macro_rules! mcpeak {
    () => {
        "K. M. McPeak et al., \"Plasmonic films can easily be better: Rules and recipes\", \
         ACS Photonics 2, 326-333 (2015), doi:10.1021/ph5004237"
    };
}

macro_rules! johnson_christy_1974 {
    () => {
        "P. B. Johnson and R. W. Christy, \"Optical constants of transition metals: Ti, V, Cr, \
         Mn, Fe, Co, Ni, and Pd\", Phys. Rev. B 9, 5056-5070 (1974), doi:10.1103/PhysRevB.9.5056"
    };
}

fn parse_builtin(cache: &'static OnceLock<Spectrum>, csv: &'static str) -> &'static Spectrum {
    cache.get_or_init(|| match Spectrum::from_csv(csv) {
        Ok(spectrum) => spectrum,
        // Unreachable: every embedded table is parsed by the crate's tests.
        Err(error) => panic!("embedded spectral table is invalid: {error}"),
    })
}

/// The metals whose measured n, k tables ship with Combustion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BuiltinMetal {
    /// Au, McPeak et al. 2015.
    Gold,
    /// Ag, McPeak et al. 2015.
    Silver,
    /// Cu, McPeak et al. 2015.
    Copper,
    /// Al, McPeak et al. 2015.
    Aluminium,
    /// Cr, Johnson & Christy 1974.
    Chromium,
    /// Ni, Johnson & Christy 1974.
    Nickel,
    /// Ti, Johnson & Christy 1974.
    Titanium,
    /// Fe, Johnson & Christy 1974.
    Iron,
    /// Pt, Tselin et al. 2024.
    Platinum,
}

impl BuiltinMetal {
    /// Every built-in metal.
    pub const ALL: [BuiltinMetal; 9] = [
        BuiltinMetal::Gold,
        BuiltinMetal::Silver,
        BuiltinMetal::Copper,
        BuiltinMetal::Aluminium,
        BuiltinMetal::Chromium,
        BuiltinMetal::Nickel,
        BuiltinMetal::Titanium,
        BuiltinMetal::Iron,
        BuiltinMetal::Platinum,
    ];

    /// Lower-case English name: `"gold"`, `"silver"`, ..., `"aluminium"`.
    pub const fn name(self) -> &'static str {
        match self {
            BuiltinMetal::Gold => "gold",
            BuiltinMetal::Silver => "silver",
            BuiltinMetal::Copper => "copper",
            BuiltinMetal::Aluminium => "aluminium",
            BuiltinMetal::Chromium => "chromium",
            BuiltinMetal::Nickel => "nickel",
            BuiltinMetal::Titanium => "titanium",
            BuiltinMetal::Iron => "iron",
            BuiltinMetal::Platinum => "platinum",
        }
    }

    /// Chemical symbol: `"Au"`, `"Ag"`, ...
    pub const fn symbol(self) -> &'static str {
        match self {
            BuiltinMetal::Gold => "Au",
            BuiltinMetal::Silver => "Ag",
            BuiltinMetal::Copper => "Cu",
            BuiltinMetal::Aluminium => "Al",
            BuiltinMetal::Chromium => "Cr",
            BuiltinMetal::Nickel => "Ni",
            BuiltinMetal::Titanium => "Ti",
            BuiltinMetal::Iron => "Fe",
            BuiltinMetal::Platinum => "Pt",
        }
    }

    /// Looks a metal up by name or chemical symbol, ignoring ASCII case and surrounding
    /// whitespace: `"gold"`/`"au"`, `"silver"`/`"ag"`, `"copper"`/`"cu"`,
    /// `"aluminium"`/`"aluminum"`/`"al"`, `"chromium"`/`"cr"`, `"nickel"`/`"ni"`,
    /// `"titanium"`/`"ti"`, `"iron"`/`"fe"`, `"platinum"`/`"pt"`.
    pub fn from_name(name: &str) -> Option<BuiltinMetal> {
        let name = name.trim();
        if name.eq_ignore_ascii_case("aluminum") {
            return Some(BuiltinMetal::Aluminium);
        }
        Self::ALL.into_iter().find(|metal| {
            name.eq_ignore_ascii_case(metal.name()) || name.eq_ignore_ascii_case(metal.symbol())
        })
    }

    /// Short label of the measured data set, e.g. `"McPeak et al. 2015"`.
    pub const fn dataset(self) -> &'static str {
        match self {
            BuiltinMetal::Gold
            | BuiltinMetal::Silver
            | BuiltinMetal::Copper
            | BuiltinMetal::Aluminium => "McPeak et al. 2015",
            BuiltinMetal::Chromium
            | BuiltinMetal::Nickel
            | BuiltinMetal::Titanium
            | BuiltinMetal::Iron => "Johnson & Christy 1974",
            BuiltinMetal::Platinum => "Tselin et al. 2024",
        }
    }

    /// Full citation of the measurement and of the database it was taken from.
    pub const fn citation(self) -> &'static str {
        match self {
            BuiltinMetal::Gold => citation!(mcpeak!(), "Au/nk/McPeak.yml"),
            BuiltinMetal::Silver => citation!(mcpeak!(), "Ag/nk/McPeak.yml"),
            BuiltinMetal::Copper => citation!(mcpeak!(), "Cu/nk/McPeak.yml"),
            BuiltinMetal::Aluminium => citation!(mcpeak!(), "Al/nk/McPeak.yml"),
            BuiltinMetal::Chromium => citation!(johnson_christy_1974!(), "Cr/nk/Johnson.yml"),
            BuiltinMetal::Nickel => citation!(johnson_christy_1974!(), "Ni/nk/Johnson.yml"),
            BuiltinMetal::Titanium => citation!(johnson_christy_1974!(), "Ti/nk/Johnson.yml"),
            BuiltinMetal::Iron => citation!(johnson_christy_1974!(), "Fe/nk/Johnson.yml"),
            BuiltinMetal::Platinum => citation!(
                "A. Tselin et al., \"Exploring the dielectric function of platinum\", \
                 Phys. Rev. B 110, 195130 (2024), doi:10.1103/PhysRevB.110.195130",
                "Pt/nk/Tselin.yml"
            ),
        }
    }

    /// The embedded CSV text (citation header in `#` comments, then the rows).
    pub const fn csv(self) -> &'static str {
        match self {
            BuiltinMetal::Gold => asset!("Au_McPeak2015.csv"),
            BuiltinMetal::Silver => asset!("Ag_McPeak2015.csv"),
            BuiltinMetal::Copper => asset!("Cu_McPeak2015.csv"),
            BuiltinMetal::Aluminium => asset!("Al_McPeak2015.csv"),
            BuiltinMetal::Chromium => asset!("Cr_JohnsonChristy1974.csv"),
            BuiltinMetal::Nickel => asset!("Ni_JohnsonChristy1974.csv"),
            BuiltinMetal::Titanium => asset!("Ti_JohnsonChristy1974.csv"),
            BuiltinMetal::Iron => asset!("Fe_JohnsonChristy1974.csv"),
            BuiltinMetal::Platinum => asset!("Pt_Tselin2024.csv"),
        }
    }

    /// The measured spectrum, parsed once and cached.
    pub fn spectrum(self) -> &'static Spectrum {
        static CACHE: [OnceLock<Spectrum>; 9] = [const { OnceLock::new() }; 9];
        parse_builtin(&CACHE[self as usize], self.csv())
    }
}

/// The dielectrics whose n, k tables ship with Combustion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BuiltinDielectric {
    /// Liquid water at 25 °C, Hale & Querry 1973.
    Water,
    /// SCHOTT N-BK7 borosilicate crown glass (n from the catalog's Sellmeier formula).
    Bk7Glass,
}

impl BuiltinDielectric {
    /// Every built-in dielectric.
    pub const ALL: [BuiltinDielectric; 2] = [BuiltinDielectric::Water, BuiltinDielectric::Bk7Glass];

    /// Lower-case name: `"water"` or `"bk7"`.
    pub const fn name(self) -> &'static str {
        match self {
            BuiltinDielectric::Water => "water",
            BuiltinDielectric::Bk7Glass => "bk7",
        }
    }

    /// Looks a dielectric up by name, ignoring ASCII case and surrounding whitespace:
    /// `"water"`/`"h2o"`, `"bk7"`/`"n-bk7"`/`"bk7glass"`/`"bk7-glass"`/`"bk7_glass"`.
    pub fn from_name(name: &str) -> Option<BuiltinDielectric> {
        let name = name.trim();
        let is = |candidate: &str| name.eq_ignore_ascii_case(candidate);
        if is("water") || is("h2o") {
            Some(BuiltinDielectric::Water)
        } else if ["bk7", "n-bk7", "bk7glass", "bk7-glass", "bk7_glass"]
            .into_iter()
            .any(is)
        {
            Some(BuiltinDielectric::Bk7Glass)
        } else {
            None
        }
    }

    /// Short label of the data set.
    pub const fn dataset(self) -> &'static str {
        match self {
            BuiltinDielectric::Water => "Hale & Querry 1973",
            BuiltinDielectric::Bk7Glass => "SCHOTT catalog 2017 (Sellmeier n)",
        }
    }

    /// Full citation of the data and of the database it was taken from.
    pub const fn citation(self) -> &'static str {
        match self {
            BuiltinDielectric::Water => citation!(
                "G. M. Hale and M. R. Querry, \"Optical constants of water in the 200-nm to \
                 200-um wavelength region\", Appl. Opt. 12, 555-563 (1973), \
                 doi:10.1364/AO.12.000555",
                "H2O/nk/Hale.yml"
            ),
            BuiltinDielectric::Bk7Glass => concat!(
                "SCHOTT Zemax catalog 2017-01-20b, glass N-BK7 (n evaluated from the catalog \
                 Sellmeier formula, k tabulated); ",
                database!(),
                ", database/data/specs/schott/optical/N-BK7.yml"
            ),
        }
    }

    /// The embedded CSV text (citation header in `#` comments, then the rows).
    pub const fn csv(self) -> &'static str {
        match self {
            BuiltinDielectric::Water => asset!("Water_HaleQuerry1973.csv"),
            BuiltinDielectric::Bk7Glass => asset!("BK7_Schott2017.csv"),
        }
    }

    /// The tabulated spectrum, parsed once and cached.
    pub fn spectrum(self) -> &'static Spectrum {
        static CACHE: [OnceLock<Spectrum>; 2] = [const { OnceLock::new() }; 2];
        parse_builtin(&CACHE[self as usize], self.csv())
    }
}
