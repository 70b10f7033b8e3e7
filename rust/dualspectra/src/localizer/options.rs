//! The localizer's options: names, defaults, ranges and doc text, owned here once.
//!
//! [`OPTIONS`] is the one table every front end reads: the CLI's flags, the C key/value
//! setters, Python's keyword arguments, the MeshLab parameters and the Blender properties are
//! built from it (or pass names and values through [`Options::set`] / [`Options::from_json`]),
//! so a new option needs an entry here and nowhere else. Each option's reason to exist, and
//! the evidence for its default, is in `docs/benchmarks/options.md`.

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// Which spectra the alignment matches (the paper's ablation, kept to reproduce it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// `k` regular + `k` scale-invariant eigenvalues (the paper's method).
    #[default]
    Dual,
    /// `2k` regular (Laplace-Beltrami) eigenvalues only.
    Lbo,
    /// `2k` scale-invariant eigenvalues only.
    Si,
}

impl Mode {
    /// Every mode, the default first.
    pub const ALL: [Mode; 3] = [Mode::Dual, Mode::Lbo, Mode::Si];

    /// The name used by serde, the CLI and every binding.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Dual => "dual",
            Mode::Lbo => "lbo",
            Mode::Si => "si",
        }
    }

    /// Eigenvalues matched in the regular and the scale-invariant metric for `k`.
    pub fn counts(self, k: usize) -> (usize, usize) {
        match self {
            Mode::Dual => (k, k),
            Mode::Lbo => (2 * k, 0),
            Mode::Si => (0, 2 * k),
        }
    }
}

impl std::str::FromStr for Mode {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        let lower = s.to_ascii_lowercase();
        Mode::ALL.into_iter().find(|m| m.name() == lower).ok_or_else(|| {
            Error::InvalidArgument(format!("unknown mode '{s}' (expected dual, lbo or si)"))
        })
    }
}

impl std::fmt::Display for Mode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// How the partial shape's units relate to the full shape's (docs/algorithm.md, "Units").
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(try_from = "ScaleRepr", into = "ScaleRepr")]
pub enum Scale {
    /// The partial is in the full shape's units (a partial whose area cannot fit is refused or
    /// warned about, naming `auto`).
    #[default]
    Same,
    /// Unknown units: the factor is estimated ([`crate::Localization::scale`] reports it).
    Auto,
    /// The partial's coordinates are multiplied by this positive factor first.
    Factor(f64),
}

/// [`Scale`] as JSON: `"same"`, `"auto"` or a positive number (also as text).
#[derive(Serialize, Deserialize)]
#[serde(untagged)]
enum ScaleRepr {
    Number(f64),
    Text(String),
}

impl From<Scale> for ScaleRepr {
    fn from(s: Scale) -> Self {
        match s {
            Scale::Same => ScaleRepr::Text("same".into()),
            Scale::Auto => ScaleRepr::Text("auto".into()),
            Scale::Factor(f) => ScaleRepr::Number(f),
        }
    }
}

impl TryFrom<ScaleRepr> for Scale {
    type Error = Error;
    fn try_from(r: ScaleRepr) -> Result<Self> {
        match r {
            ScaleRepr::Number(f) => Scale::factor(f),
            ScaleRepr::Text(t) => t.parse(),
        }
    }
}

impl Scale {
    /// `Factor(f)` for a positive finite `f`.
    pub fn factor(f: f64) -> Result<Scale> {
        if f > 0.0 && f.is_finite() {
            Ok(Scale::Factor(f))
        } else {
            Err(Error::InvalidArgument(format!("scale = {f} must be same, auto or a positive number")))
        }
    }
}

impl std::str::FromStr for Scale {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "same" => Ok(Scale::Same),
            "auto" => Ok(Scale::Auto),
            t => t
                .parse::<f64>()
                .map_err(|_| Error::InvalidArgument(format!("scale = {s} must be same, auto or a positive number")))
                .and_then(Scale::factor),
        }
    }
}

impl std::fmt::Display for Scale {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Scale::Same => f.write_str("same"),
            Scale::Auto => f.write_str("auto"),
            Scale::Factor(x) => write!(f, "{x}"),
        }
    }
}

/// Parameters of the [`crate::Localizer`]. `Options::default()` gives the project's defaults
/// (not the paper's: see `docs/benchmarks/options.md`); construct with
/// `Options { k: 10, ..Options::default() }`, since fields may be added. Ranges and docs:
/// [`OPTIONS`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Options {
    /// Which spectra are matched. Default `dual`.
    pub mode: Mode,
    /// Eigenvalues per spectrum (`dual` matches k + k, `lbo`/`si` 2k). Default 20; 1..=500.
    pub k: usize,
    /// Exponent $\alpha$ of the scale-invariant factor $s = (\epsilon + K^2)^{\alpha/2}$.
    /// Default 0.33 (the paper's); 0..=2.
    pub alpha: f64,
    /// Vertices of the decimated full shape the potential is optimised on; 0: no decimation.
    /// Default 2000; 0 or 200..=200000.
    pub resolution: usize,
    /// Trust-region iterations per start. Default 8; 1..=1000 (docs/benchmarks/options.md,
    /// "`max_iterations`": more found no better regions).
    pub max_iterations: usize,
    /// Worker threads; 0: all cores. Default 0; 0..=256.
    pub threads: usize,
    /// Plane-cut starts: the side of a plane with the partial's area, normal to the first
    /// `plane_cuts` of 26 directions in the full shape's principal-axes frame (6: both ways
    /// along each axis; 14: and the 8 diagonals; 26: and the 12 face diagonals). Default 6;
    /// 0..=26.
    pub plane_cuts: usize,
    /// The partial's units: `same` as the full shape's, `auto` (estimated) or a factor its
    /// coordinates are multiplied by. Default `same`.
    pub scale: Scale,
    /// Keeps the struct extensible (construct with `..Default::default()`).
    #[doc(hidden)]
    #[serde(skip)]
    pub non_exhaustive: crate::NonExhaustive,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            mode: Mode::Dual,
            k: 20,
            alpha: crate::geometry::metric::DEFAULT_ALPHA,
            resolution: 2000,
            max_iterations: 8,
            threads: 0,
            plane_cuts: 6,
            scale: Scale::Same,
            non_exhaustive: crate::NonExhaustive::default(),
        }
    }
}

/// The type and range of an option.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "type", rename_all = "lowercase")]
pub enum OptionKind {
    /// An integer in `min..=max`.
    Int { min: u64, max: u64 },
    /// A real number in `[min, max]`.
    Float { min: f64, max: f64 },
    /// One of the names.
    Choice { choices: &'static [&'static str] },
    /// One of the names, or a positive number (as a number or as text). Listed as a choice
    /// (`"type": "choice"`, with `"positive_number": true`) for front ends that offer names only.
    #[serde(rename = "choice")]
    ChoiceOrPositive { choices: &'static [&'static str], positive_number: bool },
}

/// One option: its name (the serde field, CLI flag `--name` with `-` for `_`, C key, Python
/// keyword, MeshLab and Blender parameter), a short label, its kind and range, and its doc.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OptionSpec {
    pub name: &'static str,
    /// A short title for GUIs ("Eigenvalues k").
    pub label: &'static str,
    #[serde(flatten)]
    pub kind: OptionKind,
    /// One or two sentences for tooltips and `--help`.
    pub doc: &'static str,
}

/// Smallest optimisation mesh accepted besides 0 (a region of a few percent of it must still
/// hold enough vertices for `k` eigenvalues).
pub const MIN_RESOLUTION: usize = 200;

/// Every option, in the order front ends list them.
pub const OPTIONS: &[OptionSpec] = &[
    OptionSpec {
        name: "mode",
        label: "Spectra",
        kind: OptionKind::Choice { choices: &["dual", "lbo", "si"] },
        doc: "Spectra matched: dual (k regular + k scale-invariant eigenvalues, the paper's method), lbo (2k regular) or si (2k scale-invariant).",
    },
    OptionSpec {
        name: "k",
        label: "Eigenvalues k",
        kind: OptionKind::Int { min: 1, max: 500 },
        doc: "Eigenvalues per spectrum.",
    },
    OptionSpec {
        name: "alpha",
        label: "Scale-invariant exponent",
        kind: OptionKind::Float { min: 0.0, max: 2.0 },
        doc: "Exponent alpha of the scale-invariant metric factor (eps + K^2)^(alpha/2).",
    },
    OptionSpec {
        name: "resolution",
        label: "Optimisation vertices",
        kind: OptionKind::Int { min: 0, max: 200_000 },
        doc: "Vertices of the decimated full shape the potential is optimised on (0: no decimation; otherwise at least 200); a partial with holes gets twice that.",
    },
    OptionSpec {
        name: "max_iterations",
        label: "Iterations per start",
        kind: OptionKind::Int { min: 1, max: 1000 },
        doc: "Trust-region iterations per start.",
    },
    OptionSpec {
        name: "threads",
        label: "Threads",
        kind: OptionKind::Int { min: 0, max: 256 },
        doc: "Worker threads (0: all cores).",
    },
    OptionSpec {
        name: "plane_cuts",
        label: "Plane-cut starts",
        kind: OptionKind::Int { min: 0, max: crate::alignment::starts::MAX_PLANE_CUTS as u64 },
        doc: "Starts on the side of a plane with the partial's area, normal to the first plane_cuts of 26 directions of the full shape's principal axes (6: both ways along each axis); beside the descriptor starts, the one holding the most descriptor votes is optimised.",
    },
    OptionSpec {
        name: "scale",
        label: "Partial's units",
        kind: OptionKind::ChoiceOrPositive { choices: &["same", "auto"], positive_number: true },
        doc: "The partial's units: same (as the full shape's), auto (unknown: the factor is estimated and reported), or a positive number the partial's coordinates are multiplied by first.",
    },
];

/// Options that existed and were removed: (name, version, why). Giving one (a C key, a
/// Python keyword, a JSON name, a CLI flag) is an error saying so, not an unknown name
/// (docs/benchmarks/options.md, "`centers` and `seed`").
pub const REMOVED_OPTIONS: &[(&str, &str, &str)] = &[
    (
        "centers",
        "0.3.0",
        "the farthest-point starts it added were measured no better than the default starts at 2.5x the time",
    ),
    ("seed", "0.3.0", "it only chose the first farthest-point centre, so it changed nothing without `centers`"),
];

/// The spec of the option `name`, or an error naming it as removed ([`REMOVED_OPTIONS`]) or
/// listing the names.
pub fn option_spec(name: &str) -> Result<&'static OptionSpec> {
    if let Some((_, version, why)) = REMOVED_OPTIONS.iter().find(|r| r.0 == name) {
        return Err(Error::InvalidArgument(format!("option '{name}' was removed in {version}: {why}; leave it out")));
    }
    OPTIONS.iter().find(|s| s.name == name).ok_or_else(|| {
        let names: Vec<&str> = OPTIONS.iter().map(|s| s.name).collect();
        Error::InvalidArgument(format!("unknown option '{name}' (options: {})", names.join(", ")))
    })
}

/// Every option as JSON: `[{"name", "label", "type", "min"/"max" or "choices", "default",
/// "doc"}, ...]`, for front ends that build their parameter lists from it.
pub fn options_schema_json() -> String {
    let defaults = serde_json::to_value(Options::default()).unwrap_or_default();
    let list: Vec<serde_json::Value> = OPTIONS
        .iter()
        .map(|s| {
            let mut v = serde_json::to_value(s).unwrap_or_default();
            if let Some(o) = v.as_object_mut() {
                o.insert("default".into(), defaults[s.name].clone());
            }
            v
        })
        .collect();
    serde_json::Value::Array(list).to_string()
}

impl Options {
    /// Check every option against its range ([`OPTIONS`]); each problem is a clear
    /// `InvalidArgument` naming the option and its range.
    pub fn validate(&self) -> Result<()> {
        let values = serde_json::to_value(self).map_err(|e| Error::InvalidArgument(e.to_string()))?;
        for spec in OPTIONS {
            check_value(spec, &values[spec.name])?;
        }
        if self.resolution != 0 && self.resolution < MIN_RESOLUTION {
            return Err(Error::InvalidArgument(format!(
                "resolution = {} is too coarse: use 0 (no decimation) or at least {MIN_RESOLUTION} vertices",
                self.resolution
            )));
        }
        Ok(())
    }

    /// Set the option `name` from a JSON value (a number, or a string for a choice; a string
    /// holding a number is accepted too, for front ends that pass text). Checks the range.
    pub fn set(&mut self, name: &str, value: serde_json::Value) -> Result<()> {
        let spec = option_spec(name)?;
        let value = match (&spec.kind, value) {
            (OptionKind::Int { .. }, serde_json::Value::String(t)) => {
                serde_json::Value::from(t.trim().parse::<u64>().map_err(|_| out_of_range(spec, &t))?)
            }
            (OptionKind::Float { .. }, serde_json::Value::String(t)) => {
                let x = t.trim().parse::<f64>().map_err(|_| out_of_range(spec, &t))?;
                serde_json::Number::from_f64(x).map(serde_json::Value::Number).ok_or_else(|| out_of_range(spec, &t))?
            }
            (OptionKind::Choice { .. }, serde_json::Value::String(t)) => serde_json::Value::String(t.to_ascii_lowercase()),
            (OptionKind::ChoiceOrPositive { choices, .. }, serde_json::Value::String(t)) => {
                let lower = t.trim().to_ascii_lowercase();
                match lower.parse::<f64>() {
                    Ok(x) if !choices.contains(&lower.as_str()) => {
                        serde_json::Number::from_f64(x).map(serde_json::Value::Number).ok_or_else(|| out_of_range(spec, &t))?
                    }
                    _ => serde_json::Value::String(lower),
                }
            }
            (_, v) => v,
        };
        check_value(spec, &value)?;
        let mut all = serde_json::to_value(&*self).map_err(|e| Error::InvalidArgument(e.to_string()))?;
        all[name] = value;
        *self = serde_json::from_value(all).map_err(|e| Error::InvalidArgument(format!("{name}: {e}")))?;
        Ok(())
    }

    /// Set the option `name` from text ("20", "0.33", "dual").
    pub fn set_str(&mut self, name: &str, text: &str) -> Result<()> {
        self.set(name, serde_json::Value::String(text.to_string()))
    }

    /// The defaults with the options of a JSON object (`{"k": 10, "mode": "lbo"}`) set; an
    /// unknown name or a value out of range is an error naming it.
    pub fn from_json(text: &str) -> Result<Options> {
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| Error::InvalidArgument(format!("options are not valid JSON: {e}")))?;
        let object = value
            .as_object()
            .ok_or_else(|| Error::InvalidArgument("options must be a JSON object of name: value".into()))?;
        let mut options = Options::default();
        for (name, v) in object {
            options.set(name, v.clone())?;
        }
        options.validate()?;
        Ok(options)
    }

    /// These options as a JSON object.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).unwrap_or_default()
    }
}

fn out_of_range(spec: &OptionSpec, got: &str) -> Error {
    let range = match spec.kind {
        OptionKind::Int { min, max } => format!("an integer in {min}..={max}"),
        OptionKind::Float { min, max } => format!("a number in [{min}, {max}]"),
        OptionKind::Choice { choices } => format!("one of {}", choices.join(", ")),
        OptionKind::ChoiceOrPositive { choices, .. } => format!("{} or a positive number", choices.join(", ")),
    };
    Error::InvalidArgument(format!("{} = {got} must be {range}", spec.name))
}

fn check_value(spec: &OptionSpec, value: &serde_json::Value) -> Result<()> {
    let ok = match spec.kind {
        OptionKind::Int { min, max } => value.as_u64().is_some_and(|x| (min..=max).contains(&x)),
        OptionKind::Float { min, max } => value.as_f64().is_some_and(|x| x.is_finite() && (min..=max).contains(&x)),
        OptionKind::Choice { choices } => value.as_str().is_some_and(|x| choices.contains(&x)),
        OptionKind::ChoiceOrPositive { choices, .. } => {
            value.as_str().is_some_and(|x| choices.contains(&x)) || value.as_f64().is_some_and(|x| x > 0.0 && x.is_finite())
        }
    };
    if ok {
        Ok(())
    } else {
        Err(out_of_range(spec, value.to_string().trim_matches('"')))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_lists_every_field_and_the_defaults_are_in_range() {
        let defaults = serde_json::to_value(Options::default()).unwrap();
        let fields: Vec<&String> = defaults.as_object().unwrap().keys().collect();
        assert_eq!(fields.len(), OPTIONS.len(), "{fields:?}");
        for spec in OPTIONS {
            check_value(spec, &defaults[spec.name]).unwrap();
        }
        Options::default().validate().unwrap();
        let schema: serde_json::Value = serde_json::from_str(&options_schema_json()).unwrap();
        assert_eq!(schema[1]["name"], "k");
        assert_eq!(schema[1]["default"], 20);
        assert_eq!(schema[1]["max"], 500);
        assert_eq!(schema[0]["choices"][2], "si");
    }

    #[test]
    fn set_checks_names_types_and_ranges() {
        let mut o = Options::default();
        o.set("k", 12.into()).unwrap();
        o.set_str("mode", "LBO").unwrap();
        o.set_str("alpha", "0.5").unwrap();
        assert_eq!((o.k, o.mode, o.alpha), (12, Mode::Lbo, 0.5));
        let err = |r: Result<()>| r.unwrap_err().to_string();
        assert!(err(o.set("k", 0.into())).contains("k = 0 must be an integer in 1..=500"));
        assert!(err(o.set("threads", 100000.into())).contains("threads"));
        assert!(err(o.set("plane_cuts", 27.into())).contains("0..=26"));
        for (name, version, _) in REMOVED_OPTIONS {
            let e = err(o.set(name, 0.into()));
            assert!(e.contains(&format!("option '{name}' was removed in {version}")), "{e}");
            assert!(OPTIONS.iter().all(|s| s.name != *name), "{name} is both an option and removed");
        }
        assert!(err(o.set_str("alpha", "-inf")).contains("alpha"));
        assert!(err(o.set_str("mode", "both")).contains("one of dual, lbo, si"));
        assert!(err(o.set("kk", 1.into())).contains("unknown option 'kk'"));
        assert!(err(o.set("k", 2.5.into())).contains("k = 2.5"));
        o.set_str("scale", "AUTO").unwrap();
        assert_eq!(o.scale, Scale::Auto);
        o.set_str("scale", "0.001").unwrap();
        assert_eq!(o.scale, Scale::Factor(0.001));
        o.set("scale", 1000.into()).unwrap();
        assert_eq!(o.scale, Scale::Factor(1000.0));
        assert!(err(o.set_str("scale", "0")).contains("same, auto or a positive number"));
        assert!(err(o.set("scale", (-2.0).into())).contains("same, auto or a positive number"));
        assert!(err(o.set_str("scale", "metres")).contains("same, auto or a positive number"));
        assert_eq!(o.scale, Scale::Factor(1000.0));
        assert_eq!(o.k, 12, "a refused value leaves the options unchanged");
    }

    #[test]
    fn from_json_round_trips_and_validates() {
        let o = Options { k: 7, plane_cuts: 14, ..Options::default() };
        assert_eq!(Options::from_json(&o.to_json()).unwrap(), o);
        for scale in [Scale::Same, Scale::Auto, Scale::Factor(0.01)] {
            let o = Options { scale, ..Options::default() };
            assert_eq!(Options::from_json(&o.to_json()).unwrap(), o);
        }
        assert_eq!(Options::from_json("{}").unwrap(), Options::default());
        assert!(Options::from_json("{\"resolution\": 50}").unwrap_err().to_string().contains("too coarse"));
        assert!(Options::from_json("[1]").is_err());
        let e = Options::from_json(r#"{"k": 8, "seed": 0}"#).unwrap_err().to_string();
        assert!(e.contains("option 'seed' was removed"), "{e}");
    }
}
