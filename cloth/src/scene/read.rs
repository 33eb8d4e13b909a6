//! Reading a scene: the file (bounded in size), TOML syntax, then each table
//! into its fields (the `Reader`), before the cross-field checks of
//! `validate.rs`.

use std::collections::BTreeSet;
use std::fmt;
use std::path::Path;

use toml::{Table, Value};

use super::{
    ClothSpec, Collider, DEFAULT_SKIN, INEXTENSIBLE, MAX_SCENE_BYTES, Material, Plane, Scene,
    SceneError, SimulationSpec, grid_too_large,
};
use crate::method::Method;

impl Scene {
    /// Read and check a scene file.
    pub fn load(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let file = path.display().to_string();
        let io = |source| SceneError::Io {
            file: file.clone(),
            source,
        };
        // Read at most MAX_SCENE_BYTES (+1 to tell a file of exactly that
        // size from a longer one): `symlab cloth /dev/zero` must not read
        // until memory runs out.
        let mut text = String::new();
        std::fs::File::open(path)
            .and_then(|f| {
                use std::io::Read;
                f.take(MAX_SCENE_BYTES + 1).read_to_string(&mut text)
            })
            .map_err(io)?;
        if text.len() as u64 > MAX_SCENE_BYTES {
            return Err(SceneError::Io {
                file,
                source: std::io::Error::other(format!(
                    "larger than the limit of {} MiB for a scene file",
                    MAX_SCENE_BYTES >> 20
                )),
            });
        }
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        Scene::parse(&text, &file, &stem)
    }

    /// Check a scene given as text; `file` names it in errors and is the
    /// default name.
    pub fn from_toml(text: &str, file: &str) -> Result<Scene, SceneError> {
        let stem = Path::new(file)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| file.to_string());
        Scene::parse(text, file, &stem)
    }

    fn parse(text: &str, file: &str, stem: &str) -> Result<Scene, SceneError> {
        let root: Table = text
            .parse()
            .map_err(|e: toml::de::Error| SceneError::Syntax {
                file: file.to_string(),
                message: e.to_string().trim_end().to_string(),
            })?;
        let r = Reader { file };
        r.keys(
            &root,
            "",
            &[
                "name",
                "description",
                "gravity",
                "cloth",
                "material",
                "pins",
                "colliders",
                "simulation",
            ],
        )?;
        let name = r
            .opt_string(&root, "", "name")?
            .unwrap_or_else(|| stem.to_string());
        let description = r.opt_string(&root, "", "description")?;
        let gravity = r.opt_vec3(&root, "", "gravity")?.unwrap_or([0.0; 3]);

        let cloth = r.cloth(r.req_table(&root, "", "cloth")?)?;
        let material = r.material(r.req_table(&root, "", "material")?)?;
        let pins = match root.get("pins") {
            None => Vec::new(),
            Some(_) => r.pins(r.req_table(&root, "", "pins")?, &cloth)?,
        };
        if pins.len() == cloth.nx * cloth.ny {
            return Err(r.err("pins", "every particle is pinned: nothing can move"));
        }
        let colliders = match root.get("colliders") {
            None => Vec::new(),
            Some(Value::Array(items)) => {
                let mut out = Vec::with_capacity(items.len());
                for (k, item) in items.iter().enumerate() {
                    let path = format!("colliders[{k}]");
                    match item {
                        Value::Table(t) => out.push(r.collider(t, &path)?),
                        other => {
                            return Err(
                                r.err(&path, format!("expected a table, found {}", kind(other)))
                            );
                        }
                    }
                }
                out
            }
            Some(other) => {
                return Err(r.err(
                    "colliders",
                    format!(
                        "expected an array of tables ([[colliders]]), found {}",
                        kind(other)
                    ),
                ));
            }
        };
        let simulation =
            r.simulation(r.req_table(&root, "", "simulation")?, material.inextensible)?;
        let scene_name = name;
        let scene = Scene {
            name: String::new(),
            description,
            cloth,
            material,
            pins,
            gravity,
            colliders,
            simulation,
        };
        // The cross-field checks (springs present), reported under the file's name.
        let named = Scene {
            name: file.to_string(),
            ..scene
        };
        named.validate()?;
        let scene = Scene {
            name: scene_name,
            ..named
        };
        Ok(scene)
    }
}

fn kind(v: &Value) -> &'static str {
    match v {
        Value::String(_) => "a string",
        Value::Integer(_) => "an integer",
        Value::Float(_) => "a float",
        Value::Boolean(_) => "a boolean",
        Value::Datetime(_) => "a date",
        Value::Array(_) => "an array",
        Value::Table(_) => "a table",
    }
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

/// Reads fields out of TOML tables, naming the file and field in errors.
pub(super) struct Reader<'a> {
    pub(super) file: &'a str,
}

impl Reader<'_> {
    pub(super) fn err(&self, field: &str, message: impl fmt::Display) -> SceneError {
        SceneError::Field {
            file: self.file.to_string(),
            field: field.to_string(),
            message: message.to_string(),
        }
    }

    /// Refuse keys outside `allowed`.
    fn keys(&self, t: &Table, path: &str, allowed: &[&str]) -> Result<(), SceneError> {
        for key in t.keys() {
            if !allowed.contains(&key.as_str()) {
                let place = if path.is_empty() {
                    "at the top level".to_string()
                } else {
                    format!("in [{path}]")
                };
                return Err(self.err(
                    &join(path, key),
                    format!(
                        "unknown key `{key}` {place} (expected one of: {})",
                        allowed.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    fn req<'t>(&self, t: &'t Table, path: &str, key: &str) -> Result<&'t Value, SceneError> {
        t.get(key).ok_or_else(|| {
            let place = if path.is_empty() {
                "the scene".to_string()
            } else {
                format!("[{path}]")
            };
            self.err(&join(path, key), format!("missing (required in {place})"))
        })
    }

    fn req_table<'t>(&self, t: &'t Table, path: &str, key: &str) -> Result<&'t Table, SceneError> {
        match self.req(t, path, key)? {
            Value::Table(v) => Ok(v),
            other => Err(self.err(
                &join(path, key),
                format!("expected a table, found {}", kind(other)),
            )),
        }
    }

    fn number(&self, v: &Value, field: &str) -> Result<f64, SceneError> {
        let x = match v {
            Value::Float(x) => *x,
            Value::Integer(i) => *i as f64,
            other => {
                return Err(self.err(field, format!("expected a number, found {}", kind(other))));
            }
        };
        if !x.is_finite() {
            return Err(self.err(field, format!("must be finite (got {x})")));
        }
        Ok(x)
    }

    fn opt_f64(&self, t: &Table, path: &str, key: &str) -> Result<Option<f64>, SceneError> {
        t.get(key)
            .map(|v| self.number(v, &join(path, key)))
            .transpose()
    }

    fn req_f64(&self, t: &Table, path: &str, key: &str) -> Result<f64, SceneError> {
        self.number(self.req(t, path, key)?, &join(path, key))
    }

    fn positive(&self, x: f64, field: &str) -> Result<f64, SceneError> {
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(field, format!("must be positive (got {x})")))
        }
    }

    fn non_negative(&self, x: f64, field: &str) -> Result<f64, SceneError> {
        if x >= 0.0 {
            Ok(x)
        } else {
            Err(self.err(field, format!("must not be negative (got {x})")))
        }
    }

    fn integer(&self, v: &Value, field: &str) -> Result<i64, SceneError> {
        match v {
            Value::Integer(i) => Ok(*i),
            other => Err(self.err(field, format!("expected an integer, found {}", kind(other)))),
        }
    }

    fn count(&self, t: &Table, path: &str, key: &str, min: usize) -> Result<usize, SceneError> {
        let field = join(path, key);
        let i = self.integer(self.req(t, path, key)?, &field)?;
        if i < min as i64 {
            return Err(self.err(&field, format!("must be at least {min} (got {i})")));
        }
        usize::try_from(i).map_err(|_| self.err(&field, format!("too large (got {i})")))
    }

    fn opt_string(&self, t: &Table, path: &str, key: &str) -> Result<Option<String>, SceneError> {
        match t.get(key) {
            None => Ok(None),
            Some(Value::String(s)) => Ok(Some(s.clone())),
            Some(other) => Err(self.err(
                &join(path, key),
                format!("expected a string, found {}", kind(other)),
            )),
        }
    }

    fn string_value<'v>(&self, v: &'v Value, field: &str) -> Result<&'v str, SceneError> {
        match v {
            Value::String(s) => Ok(s),
            other => Err(self.err(field, format!("expected a string, found {}", kind(other)))),
        }
    }

    fn vec3(&self, v: &Value, field: &str) -> Result<[f64; 3], SceneError> {
        match v {
            Value::Array(items) if items.len() == 3 => {
                let mut out = [0.0; 3];
                for (k, x) in items.iter().enumerate() {
                    out[k] = self.number(x, &format!("{field}[{k}]"))?;
                }
                Ok(out)
            }
            Value::Array(items) => Err(self.err(
                field,
                format!("expected 3 numbers [x, y, z], found {}", items.len()),
            )),
            other => Err(self.err(
                field,
                format!("expected an array [x, y, z], found {}", kind(other)),
            )),
        }
    }

    fn opt_vec3(&self, t: &Table, path: &str, key: &str) -> Result<Option<[f64; 3]>, SceneError> {
        t.get(key)
            .map(|v| self.vec3(v, &join(path, key)))
            .transpose()
    }

    fn req_vec3(&self, t: &Table, path: &str, key: &str) -> Result<[f64; 3], SceneError> {
        self.vec3(self.req(t, path, key)?, &join(path, key))
    }

    fn str_array<'v>(
        &self,
        t: &'v Table,
        path: &str,
        key: &str,
    ) -> Result<Vec<(String, &'v str)>, SceneError> {
        let field = join(path, key);
        match t.get(key) {
            None => Ok(Vec::new()),
            Some(Value::Array(items)) => items
                .iter()
                .enumerate()
                .map(|(k, v)| {
                    let f = format!("{field}[{k}]");
                    self.string_value(v, &f).map(|s| (f, s))
                })
                .collect(),
            Some(other) => Err(self.err(
                &field,
                format!("expected an array of strings, found {}", kind(other)),
            )),
        }
    }

    fn cloth(&self, t: &Table) -> Result<ClothSpec, SceneError> {
        let p = "cloth";
        self.keys(
            t,
            p,
            &[
                "width",
                "height",
                "nx",
                "ny",
                "origin",
                "plane",
                "prestretch",
                "sag",
            ],
        )?;
        let width = self.positive(self.req_f64(t, p, "width")?, "cloth.width")?;
        let height = self.positive(self.req_f64(t, p, "height")?, "cloth.height")?;
        let nx = self.count(t, p, "nx", 2)?;
        let ny = self.count(t, p, "ny", 2)?;
        if let Some((which, message)) = grid_too_large(nx, ny) {
            return Err(self.err(&format!("cloth.{which}"), message));
        }
        let origin = self.opt_vec3(t, p, "origin")?.unwrap_or([0.0; 3]);
        let plane = match t.get("plane") {
            None => Plane::Horizontal,
            Some(v) => {
                match self.string_value(v, "cloth.plane")? {
                    "horizontal" => Plane::Horizontal,
                    "vertical" => Plane::Vertical,
                    other => {
                        return Err(self.err(
                        "cloth.plane",
                        format!("unknown plane \"{other}\" (expected \"horizontal\" or \"vertical\")"),
                    ));
                    }
                }
            }
        };
        let prestretch = match self.opt_f64(t, p, "prestretch")? {
            None => 1.0,
            Some(s) => self.positive(s, "cloth.prestretch")?,
        };
        let sag = match self.opt_f64(t, p, "sag")? {
            None => 0.0,
            Some(s) => self.non_negative(s, "cloth.sag")?,
        };
        Ok(ClothSpec {
            width,
            height,
            nx,
            ny,
            origin,
            plane,
            prestretch,
            sag,
        })
    }

    fn material(&self, t: &Table) -> Result<Material, SceneError> {
        let p = "material";
        self.keys(t, p, &["density", "stretch", "shear", "bend", "bending"])?;
        let density = self.positive(self.req_f64(t, p, "density")?, "material.density")?;
        let family = |key: &str| -> Result<Option<f64>, SceneError> {
            match self.opt_f64(t, p, key)? {
                None => Ok(None),
                Some(k) => {
                    let k = self.non_negative(k, &join(p, key))?;
                    Ok((k > 0.0).then_some(k))
                }
            }
        };
        // `stretch = "inextensible"`: warp and weft edges are length
        // constraints instead of springs (a number keeps the spring model).
        let inextensible = match t.get("stretch") {
            Some(Value::String(s)) if s == INEXTENSIBLE => true,
            Some(Value::String(s)) => {
                return Err(self.err(
                    "material.stretch",
                    format!(
                        "expected a stiffness (N per unit strain) or \"{INEXTENSIBLE}\", found the string \"{s}\""
                    ),
                ));
            }
            _ => false,
        };
        // `bending`: N·m, finite and not negative; an inextensible sheet
        // without it gets the light cotton default, a spring cloth none.
        let bending = match self.opt_f64(t, p, "bending")? {
            Some(b) => {
                let b = self.non_negative(b, "material.bending")?;
                if b > 0.0 && !inextensible {
                    return Err(self.err(
                        "material.bending",
                        format!(
                            "{b:e} N·m: the isometric bending energy is for an inextensible sheet (material.stretch = \"{INEXTENSIBLE}\"), whose motion is the isometric one it assumes; a spring cloth bends with `bend` springs"
                        ),
                    ));
                }
                b
            }
            None if inextensible => super::DEFAULT_BENDING,
            None => 0.0,
        };
        Ok(Material {
            density,
            bending,
            stretch: if inextensible {
                None
            } else {
                family("stretch")?
            },
            shear: family("shear")?,
            bend: family("bend")?,
            inextensible,
        })
    }

    fn pins(&self, t: &Table, cloth: &ClothSpec) -> Result<Vec<(usize, usize)>, SceneError> {
        let p = "pins";
        self.keys(t, p, &["edges", "corners", "points"])?;
        let (nx, ny) = (cloth.nx, cloth.ny);
        let mut set = BTreeSet::new();
        for (field, edge) in self.str_array(t, p, "edges")? {
            match edge {
                "top" => set.extend((0..nx).map(|i| (i, 0))),
                "bottom" => set.extend((0..nx).map(|i| (i, ny - 1))),
                "left" => set.extend((0..ny).map(|j| (0, j))),
                "right" => set.extend((0..ny).map(|j| (nx - 1, j))),
                other => {
                    return Err(self.err(
                        &field,
                        format!("unknown edge \"{other}\" (expected \"top\" (j = 0), \"bottom\" (j = ny − 1), \"left\" (i = 0) or \"right\" (i = nx − 1))"),
                    ));
                }
            }
        }
        for (field, corner) in self.str_array(t, p, "corners")? {
            set.insert(match corner {
                "top-left" => (0, 0),
                "top-right" => (nx - 1, 0),
                "bottom-left" => (0, ny - 1),
                "bottom-right" => (nx - 1, ny - 1),
                other => {
                    return Err(self.err(
                        &field,
                        format!("unknown corner \"{other}\" (expected \"top-left\", \"top-right\", \"bottom-left\" or \"bottom-right\")"),
                    ));
                }
            });
        }
        match t.get("points") {
            None => {}
            Some(Value::Array(items)) => {
                for (k, v) in items.iter().enumerate() {
                    let field = format!("pins.points[{k}]");
                    let ij = match v {
                        Value::Array(pair) if pair.len() == 2 => [
                            self.integer(&pair[0], &format!("{field}[0]"))?,
                            self.integer(&pair[1], &format!("{field}[1]"))?,
                        ],
                        _ => return Err(self.err(&field, "expected a pair of integers [i, j]")),
                    };
                    if ij[0] < 0 || ij[1] < 0 || ij[0] >= nx as i64 || ij[1] >= ny as i64 {
                        return Err(self.err(
                            &field,
                            format!(
                                "({}, {}) is outside the {nx} × {ny} grid (0 ≤ i < {nx}, 0 ≤ j < {ny})",
                                ij[0], ij[1]
                            ),
                        ));
                    }
                    set.insert((ij[0] as usize, ij[1] as usize));
                }
            }
            Some(other) => {
                return Err(self.err(
                    "pins.points",
                    format!("expected an array of [i, j] pairs, found {}", kind(other)),
                ));
            }
        }
        Ok(set.into_iter().collect())
    }

    fn collider(&self, t: &Table, path: &str) -> Result<Collider, SceneError> {
        let ty = self.string_value(self.req(t, path, "type")?, &join(path, "type"))?;
        let stiffness =
            |r: &Self| r.positive(r.req_f64(t, path, "stiffness")?, &join(path, "stiffness"));
        let skin = |r: &Self| -> Result<f64, SceneError> {
            match r.opt_f64(t, path, "skin")? {
                None => Ok(DEFAULT_SKIN),
                Some(s) => r.non_negative(s, &join(path, "skin")),
            }
        };
        match ty {
            "plane" => {
                self.keys(t, path, &["type", "point", "normal", "stiffness", "skin"])?;
                let point = self.req_vec3(t, path, "point")?;
                let n = self.req_vec3(t, path, "normal")?;
                let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                if !(len > 0.0 && len.is_finite()) {
                    return Err(self.err(&join(path, "normal"), "must be a nonzero vector"));
                }
                Ok(Collider::Plane {
                    point,
                    normal: [n[0] / len, n[1] / len, n[2] / len],
                    stiffness: stiffness(self)?,
                    skin: skin(self)?,
                })
            }
            "sphere" => {
                self.keys(t, path, &["type", "center", "radius", "stiffness", "skin"])?;
                let center = self.req_vec3(t, path, "center")?;
                let radius =
                    self.positive(self.req_f64(t, path, "radius")?, &join(path, "radius"))?;
                Ok(Collider::Sphere {
                    center,
                    radius,
                    stiffness: stiffness(self)?,
                    skin: skin(self)?,
                })
            }
            other => Err(self.err(
                &join(path, "type"),
                format!("unknown collider type \"{other}\" (expected \"plane\" or \"sphere\")"),
            )),
        }
    }

    /// `inextensible`: the scene's sheet is constrained, so `substeps` may
    /// be left out (it is then `"auto"`), and its step is variable unless
    /// `step = "fixed"`.
    fn simulation(&self, t: &Table, inextensible: bool) -> Result<SimulationSpec, SceneError> {
        let p = "simulation";
        self.keys(
            t,
            p,
            &[
                "frame_rate",
                "substeps",
                "frames",
                "method",
                "step",
                "wave_number",
                "max_substeps",
            ],
        )?;
        let frame_rate = match self.opt_f64(t, p, "frame_rate")? {
            None => 60.0,
            Some(r) => self.positive(r, "simulation.frame_rate")?,
        };
        // `substeps = "auto"` (the default of an inextensible sheet): the
        // step is chosen from the model's stability estimate when the run
        // is planned (`crate::schedule::auto_step`); until then 1.
        let auto_substeps = match t.get("substeps") {
            Some(Value::String(s)) if s == "auto" => true,
            Some(Value::String(s)) => {
                return Err(self.err(
                    "simulation.substeps",
                    format!("expected a whole number of steps per frame or \"auto\", found the string \"{s}\""),
                ));
            }
            None => inextensible,
            Some(_) => false,
        };
        let substeps = if auto_substeps {
            1
        } else {
            self.count(t, p, "substeps", 1)?
        };
        let variable = self.variable_step(t, inextensible)?;
        let frames = self.count(t, p, "frames", 0)?;
        let method = self.string_value(self.req(t, p, "method")?, "simulation.method")?;
        Method::parse(method).map_err(|e| self.err("simulation.method", e))?;
        Ok(SimulationSpec {
            frame_rate,
            substeps,
            auto_substeps,
            variable,
            frames,
            method: method.to_string(),
        })
    }

    /// `step` (`"variable"`, the default of an inextensible sheet, or
    /// `"fixed"`), and the variable step's `wave_number` (in (0, 2): RATTLE
    /// is stable only below 2) and `max_substeps` (at least 2).
    fn variable_step(
        &self,
        t: &Table,
        inextensible: bool,
    ) -> Result<Option<super::VariableStep>, SceneError> {
        let p = "simulation";
        let variable = match self.opt_string(t, p, "step")?.as_deref() {
            None => inextensible,
            Some("variable") if inextensible => true,
            Some("variable") => {
                return Err(self.err(
                    "simulation.step",
                    "\"variable\" is RATTLE's reversible variable step, for an inextensible sheet (material.stretch = \"inextensible\"); a spring scene takes \"fixed\"",
                ));
            }
            Some("fixed") => false,
            Some(other) => {
                return Err(self.err(
                    "simulation.step",
                    format!("expected \"variable\" or \"fixed\", found \"{other}\""),
                ));
            }
        };
        if !variable {
            for key in ["wave_number", "max_substeps"] {
                if t.contains_key(key) {
                    return Err(self.err(
                        &join(p, key),
                        "belongs to the variable step (step = \"variable\"); this scene's step is fixed",
                    ));
                }
            }
            return Ok(None);
        }
        let mut v = super::VariableStep::default();
        if let Some(w) = self.opt_f64(t, p, "wave_number")? {
            if !(w > 0.0 && w < 2.0) {
                return Err(self.err(
                    "simulation.wave_number",
                    format!("must lie between 0 and 2, RATTLE's stability limit of h·ω (got {w})"),
                ));
            }
            v.wave_number = w;
        }
        if t.contains_key("max_substeps") {
            v.max_substeps = self.count(t, p, "max_substeps", 2)?;
        }
        Ok(Some(v))
    }
}
