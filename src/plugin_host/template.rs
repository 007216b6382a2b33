//! New plugin crates from a declaration (thesis fig. 4.8): module name, parameters with
//! initial values (and ranges), helper functions and logged data series become a crate
//! in the plugin workspace that builds as it is, with the step function left to write.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::plugin_host::error::{DeclProblem, PluginError};
use crate::plugin_host::library::valid_module_name;

/// One declared parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamDecl {
    /// Parameter name (as in actuation files).
    pub name: String,
    /// Initial value.
    pub initial: f64,
    /// Lowest allowed value.
    pub min: f64,
    /// Highest allowed value.
    pub max: f64,
}

impl ParamDecl {
    /// `name=value` (range −10|v|..10|v|, at least −100..100) or `name=value:min..max`.
    pub fn parse(spec: &str) -> Result<ParamDecl, PluginError> {
        let bad = |why: String| PluginError::Param {
            spec: spec.to_string(),
            why,
        };
        let (name, rest) = spec
            .split_once('=')
            .ok_or_else(|| bad("expected NAME=VALUE or NAME=VALUE:MIN..MAX".into()))?;
        let number = |t: &str| {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(format!("{t:?} is not a finite number")))
        };
        let (initial, range) = match rest.split_once(':') {
            Some((v, range)) => {
                let (lo, hi) = range
                    .split_once("..")
                    .ok_or_else(|| bad("the range is MIN..MAX".into()))?;
                (number(v)?, Some((number(lo)?, number(hi)?)))
            }
            None => (number(rest)?, None),
        };
        let (min, max) = range.unwrap_or_else(|| {
            let span = (initial.abs() * 10.0).max(100.0);
            (-span, span)
        });
        Ok(ParamDecl {
            name: name.trim().to_string(),
            initial,
            min,
            max,
        })
    }
}

/// A module to generate.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Declaration {
    /// Registry name (letters, digits, `_`).
    pub name: String,
    /// One line on what the module does.
    pub summary: String,
    /// The module's parameters.
    pub params: Vec<ParamDecl>,
    /// Helper function names (generated as `fn NAME(x: f64) -> f64`).
    pub helpers: Vec<String>,
    /// Logged data series.
    pub series: Vec<String>,
}

/// Whether `s` is a Rust identifier we can generate (ASCII, not a keyword).
fn identifier(s: &str) -> bool {
    const KEYWORDS: &[&str] = &[
        "as", "break", "const", "continue", "crate", "else", "enum", "extern", "false", "fn",
        "for", "if", "impl", "in", "let", "loop", "match", "mod", "move", "mut", "pub", "ref",
        "return", "self", "static", "struct", "super", "trait", "true", "type", "unsafe", "use",
        "where", "while", "async", "await", "dyn", "gen",
    ];
    s.chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !KEYWORDS.contains(&s)
}

/// `MyGait` → `my_gait`, `Phase Lag` → `phase_lag`.
pub fn snake_case(s: &str) -> String {
    let mut out = String::new();
    let mut prev_lower = false;
    for c in s.chars() {
        if c.is_ascii_uppercase() {
            if prev_lower {
                out.push('_');
            }
            out.push(c.to_ascii_lowercase());
            prev_lower = false;
        } else if c.is_ascii_alphanumeric() {
            out.push(c);
            prev_lower = c.is_ascii_lowercase() || c.is_ascii_digit();
        } else {
            if !out.ends_with('_') && !out.is_empty() {
                out.push('_');
            }
            prev_lower = false;
        }
    }
    out.trim_matches('_').to_string()
}

fn constant(s: &str) -> String {
    snake_case(s).to_ascii_uppercase()
}

impl Declaration {
    /// The crate (and folder) name.
    pub fn crate_name(&self) -> String {
        snake_case(&self.name)
    }

    /// Every problem of the declaration, or `Ok`.
    pub fn validate(&self) -> Result<(), PluginError> {
        let mut problems = Vec::new();
        if !valid_module_name(&self.name) {
            problems.push(DeclProblem::ModuleName(self.name.clone()));
        }
        let mut seen = Vec::new();
        for p in &self.params {
            if !identifier(&snake_case(&p.name)) || p.name.contains('"') {
                problems.push(DeclProblem::ParamName(p.name.clone()));
            }
            if !(p.min <= p.initial && p.initial <= p.max) {
                problems.push(DeclProblem::Initial {
                    name: p.name.clone(),
                    initial: p.initial,
                    min: p.min,
                    max: p.max,
                });
            }
            seen.push(constant(&p.name));
        }
        for s in &self.series {
            if !identifier(&snake_case(s)) || s.contains('"') {
                problems.push(DeclProblem::SeriesName(s.clone()));
            }
            seen.push(format!("SERIES_{}", constant(s)));
        }
        for h in &self.helpers {
            if !identifier(h) {
                problems.push(DeclProblem::HelperName(h.clone()));
            }
            seen.push(h.clone());
        }
        seen.sort();
        for w in seen.windows(2) {
            if w[0] == w[1] {
                problems.push(DeclProblem::Twice(w[0].clone()));
            }
        }
        if problems.is_empty() {
            Ok(())
        } else {
            Err(PluginError::Declaration(problems))
        }
    }

    /// The crate's `Cargo.toml` (in the plugin workspace, next to `api/`).
    pub fn cargo_toml(&self) -> String {
        format!(
            "[package]\nname = \"{}\"\nversion = \"0.1.0\"\nedition.workspace = true\n\
             rust-version.workspace = true\npublish = false\n\n[lib]\ncrate-type = [\"cdylib\"]\n\n\
             [dependencies]\nproleg-plugin-api = {{ path = \"../api\" }}\n",
            self.crate_name()
        )
    }

    /// The crate's `src/lib.rs`: constants, the module type, helpers, the export.
    pub fn lib_rs(&self) -> String {
        let ty = self.name.replace('_', "");
        let mut s = String::new();
        let summary = if self.summary.is_empty() {
            "a user module"
        } else {
            &self.summary
        };
        self.lib_header(&mut s, &ty, summary);
        self.module_impl(&mut s, &ty, summary);
        self.compute_fn(&mut s);
        for h in &self.helpers {
            let _ = writeln!(
                s,
                "\n/// Helper `{h}`: fill in.\nfn {h}(x: f64) -> f64 {{\n    helpers::wrap_tau(x)\n}}"
            );
        }
        let _ = writeln!(s, "\nexport_module!({ty});");
        s
    }

    /// The crate docs, imports, parameter and series constants and the state struct.
    fn lib_header(&self, s: &mut String, ty: &str, summary: &str) {
        let _ = writeln!(s, "//! `{}`: {summary}.", self.name);
        s.push_str("//! Made with `proleg plugin new`; build with `proleg plugin build ");
        let _ = writeln!(s, "{}`.\n", self.crate_name());
        s.push_str("#![allow(dead_code)]\n\n");
        s.push_str(
            "use proleg_plugin_api::{Context, Data, Module, Param, Params, export_module, helpers};\n\n",
        );
        s.push_str("// Parameters (index into PARAMETERS).\n");
        for (i, p) in self.params.iter().enumerate() {
            let _ = writeln!(s, "const {}: usize = {i};", constant(&p.name));
        }
        s.push_str("// Logged data series (index into SERIES).\n");
        for (i, d) in self.series.iter().enumerate() {
            let _ = writeln!(s, "const SERIES_{}: usize = {i};", constant(d));
        }
        let _ = writeln!(
            s,
            "\n/// The module's state.\n#[derive(Clone)]\nstruct {ty} {{\n    /// \
             Per joint: time since the start (s); replace with your own state.\n    \
             clock: Vec<f64>,\n}}\n"
        );
    }

    /// `impl Module`: name, summary, parameters, series, `new` and `reset`.
    fn module_impl(&self, s: &mut String, ty: &str, summary: &str) {
        let _ = writeln!(s, "impl Module for {ty} {{");
        let _ = writeln!(s, "    const NAME: &'static str = \"{}\";", self.name);
        let _ = writeln!(
            s,
            "    const SUMMARY: &'static str = \"{}\";",
            summary.replace('"', "'")
        );
        s.push_str("    const PARAMETERS: &'static [Param] = &[\n");
        for p in &self.params {
            let _ = writeln!(
                s,
                "        Param::new(\"{}\", {:?}, {:?}, {:?}),",
                p.name, p.initial, p.min, p.max
            );
        }
        s.push_str("    ];\n    const SERIES: &'static [&'static str] = &[");
        let series: Vec<String> = self.series.iter().map(|d| format!("\"{d}\"")).collect();
        s.push_str(&series.join(", "));
        s.push_str("];\n\n");
        let _ = writeln!(
            s,
            "    fn new(joints: usize) -> Self {{\n        {ty} {{\n            clock: vec![0.0; joints],\n        }}\n    }}\n"
        );
        s.push_str(
            "    fn reset(&mut self, _seed: u64) {\n        self.clock.fill(0.0);\n    }\n\n",
        );
    }

    /// `compute` (the step), which closes the `impl Module` block.
    fn compute_fn(&self, s: &mut String) {
        s.push_str(
            "    fn compute(&mut self, ctx: &Context, p: &Params, out: &mut [f64], data: &mut Data) {\n",
        );
        s.push_str("        for (j, angle) in out.iter_mut().enumerate() {\n");
        s.push_str("            // The angle (degrees) of joint j at time ctx.time.\n");
        for p in &self.params {
            let _ = writeln!(
                s,
                "            let {} = p.get({}, j);",
                snake_case(&p.name),
                constant(&p.name)
            );
        }
        s.push_str("            self.clock[j] += ctx.dt;\n            *angle = 0.0;\n");
        for d in &self.series {
            let _ = writeln!(
                s,
                "            data.set(SERIES_{}, j, self.clock[j]);",
                constant(d)
            );
        }
        for p in &self.params {
            let _ = writeln!(s, "            let _ = {};", snake_case(&p.name));
        }
        s.push_str("        }\n    }\n}\n");
    }

    /// Writes the crate into the plugin workspace; refuses to overwrite a crate.
    pub fn create(&self, workspace: &Path) -> Result<PathBuf, PluginError> {
        self.validate()?;
        if !workspace.join("api").join("Cargo.toml").is_file() {
            return Err(PluginError::NotAWorkspace(workspace.to_path_buf()));
        }
        let folder = workspace.join(self.crate_name());
        if folder.exists() {
            return Err(PluginError::Exists(folder));
        }
        self.write(&folder)?;
        Ok(folder)
    }

    /// Writes (or overwrites) the crate's manifest and source in `folder`.
    pub fn write(&self, folder: &Path) -> Result<(), PluginError> {
        let src = folder.join("src");
        std::fs::create_dir_all(&src).map_err(PluginError::io("creating", &src))?;
        let manifest = folder.join("Cargo.toml");
        std::fs::write(&manifest, self.cargo_toml())
            .map_err(PluginError::io("writing", &manifest))?;
        let lib = src.join("lib.rs");
        std::fs::write(&lib, self.lib_rs()).map_err(PluginError::io("writing", &lib))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parameters_parse_with_and_without_ranges() {
        let p = ParamDecl::parse("amplitude=30").unwrap();
        assert_eq!((p.initial, p.min, p.max), (30.0, -300.0, 300.0));
        let p = ParamDecl::parse("period=1.5:0.1..10").unwrap();
        assert_eq!(
            (p.name.as_str(), p.initial, p.min, p.max),
            ("period", 1.5, 0.1, 10.0)
        );
        for bad in ["period", "period=nan", "period=1:5"] {
            assert!(
                matches!(ParamDecl::parse(bad), Err(PluginError::Param { .. })),
                "{bad}"
            );
        }
    }

    #[test]
    fn declarations_are_checked_and_generate_the_declared_items() {
        let d = Declaration {
            name: "MyGait".into(),
            summary: String::new(),
            params: vec![
                ParamDecl::parse("amplitude=30").unwrap(),
                ParamDecl::parse("period=1:0.1..10").unwrap(),
            ],
            helpers: vec!["smooth".into()],
            series: vec!["phase".into()],
        };
        d.validate().unwrap();
        assert_eq!(d.crate_name(), "my_gait");
        let src = d.lib_rs();
        for needle in [
            "const AMPLITUDE: usize = 0;",
            "const PERIOD: usize = 1;",
            "const SERIES_PHASE: usize = 0;",
            "Param::new(\"period\", 1.0, 0.1, 10.0)",
            "const NAME: &'static str = \"MyGait\";",
            "fn smooth(x: f64) -> f64",
            "export_module!(MyGait);",
        ] {
            assert!(src.contains(needle), "{needle} missing in\n{src}");
        }
        let bad = Declaration {
            name: "1bad".into(),
            params: vec![
                ParamDecl::parse("a=5:0..1").unwrap(),
                ParamDecl::parse("a=0").unwrap(),
            ],
            helpers: vec!["fn".into()],
            ..Declaration::default()
        };
        let Err(PluginError::Declaration(problems)) = bad.validate() else {
            panic!("the declaration was accepted");
        };
        assert_eq!(
            problems,
            vec![
                DeclProblem::ModuleName("1bad".into()),
                DeclProblem::Initial {
                    name: "a".into(),
                    initial: 5.0,
                    min: 0.0,
                    max: 1.0
                },
                DeclProblem::HelperName("fn".into()),
                DeclProblem::Twice("A".into()),
            ]
        );
    }
}
