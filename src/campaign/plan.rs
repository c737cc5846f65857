//! The plan of a campaign, read from TOML: shared `identify` options, the test conditions
//! and their units, an optional geometry, and the points. Every fault names its line.

use std::path::{Path, PathBuf};

use toml::Spanned;
use toml::de::{DeTable, DeValue};

use super::point::{Coefficient, Condition, Expectation, Point, Setting, Unit, Value};
use super::settings;
use crate::error::{Error, Result, excerpt};
use crate::job::{Channels, Geometry, Options};

/// A campaign plan: the shared `identify` options, the conditions, the geometry and the
/// points (see the [module docs](super)).
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The plan's file, as named in errors.
    pub source: String,
    /// The folder file patterns are relative to (the plan's own).
    pub base: PathBuf,
    /// The shared options (`[identify]`).
    pub shared: Vec<Setting>,
    /// The conditions (`[conditions]`), in the plan's order.
    pub conditions: Vec<Condition>,
    /// Sensor planes to the bearing plane (`[geometry]`).
    pub geometry: Option<Geometry>,
    /// The points, in the plan's order.
    pub points: Vec<Point>,
}

/// The keys a `[[point]]` table has besides its conditions.
const POINT_KEYS: [&str; 5] = ["name", "files", "baseline", "expect", "identify"];

/// Line (from 1) of byte `at` of `text`.
fn line_of(text: &str, at: usize) -> usize {
    1 + text.as_bytes()[..at.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
}

/// Reads a plan's text, naming `source` (its path) in errors.
struct Reader<'t> {
    text: &'t str,
    source: String,
}

type Item<'i> = Spanned<DeValue<'i>>;

impl<'t> Reader<'t> {
    fn line(&self, span: std::ops::Range<usize>) -> usize {
        line_of(self.text, span.start)
    }

    fn error(&self, span: std::ops::Range<usize>, message: String) -> Error {
        Error::Plan {
            file: self.source.clone(),
            line: self.line(span),
            message,
        }
    }

    fn number(&self, v: &Item<'_>, what: &str) -> Result<f64> {
        let bad = || self.error(v.span(), format!("{what}: expected a number"));
        match v.get_ref() {
            DeValue::Integer(i) => i64::from_str_radix(&i.as_str().replace('_', ""), i.radix())
                .map(|i| i as f64)
                .map_err(|_| bad()),
            DeValue::Float(x) => x.as_str().replace('_', "").parse().map_err(|_| bad()),
            _ => Err(bad()),
        }
    }

    fn string<'v>(&self, v: &'v Item<'_>, what: &str) -> Result<&'v str> {
        v.get_ref()
            .as_str()
            .ok_or_else(|| self.error(v.span(), format!("{what}: expected a string")))
    }

    fn table<'v, 'i>(&self, v: &'v Item<'i>, what: &str) -> Result<&'v DeTable<'i>> {
        v.get_ref()
            .as_table()
            .ok_or_else(|| self.error(v.span(), format!("{what}: expected a table")))
    }

    fn numbers(&self, v: &Item<'_>, what: &str) -> Result<Vec<f64>> {
        let array = v
            .get_ref()
            .as_array()
            .ok_or_else(|| self.error(v.span(), format!("{what}: expected an array of numbers")))?;
        array.iter().map(|x| self.number(x, what)).collect()
    }

    /// An option's value as the command line spells it: arrays joined by commas, numbers in
    /// their shortest round-trip form, strings and booleans as written.
    fn option_text(&self, name: &str, v: &Item<'_>) -> Result<String> {
        Ok(match v.get_ref() {
            DeValue::String(s) => s.to_string(),
            DeValue::Boolean(b) => b.to_string(),
            DeValue::Integer(_) | DeValue::Float(_) => self.number(v, name)?.to_string(),
            DeValue::Array(items) => items
                .iter()
                .map(|x| self.option_text(name, x))
                .collect::<Result<Vec<_>>>()?
                .join(","),
            _ => {
                return Err(self.error(
                    v.span(),
                    format!("`{name}`: expected a string, number, boolean or array"),
                ));
            }
        })
    }

    /// The settings of an `identify` table, each checked to be an option of `identify` that a
    /// plan can set.
    fn settings(&self, table: &DeTable<'_>) -> Result<Vec<Setting>> {
        let mut out = Vec::with_capacity(table.len());
        for (key, value) in table {
            let name = key.get_ref().replace('_', "-");
            if !settings::is_setting(&name) {
                return Err(self.error(
                    key.span(),
                    format!(
                        "unknown option `{}` in an identify table: expected one of {}",
                        excerpt(key.get_ref()),
                        settings::setting_names()
                    ),
                ));
            }
            out.push(Setting {
                text: self.option_text(&name, value)?,
                name,
                line: self.line(key.span()),
            });
        }
        Ok(out)
    }

    fn conditions(&self, table: &DeTable<'_>) -> Result<Vec<Condition>> {
        let mut out = Vec::with_capacity(table.len());
        for (key, value) in table {
            let name = key.get_ref().to_string();
            if POINT_KEYS.contains(&name.as_str()) {
                return Err(self.error(
                    key.span(),
                    format!("condition `{name}`: the name is a point key; choose another"),
                ));
            }
            let unit = self.string(value, &format!("the unit of condition `{name}`"))?;
            out.push(Condition {
                name,
                unit: Unit::parse(unit),
            });
        }
        Ok(out)
    }

    fn geometry(&self, item: &Item<'_>) -> Result<Geometry> {
        let table = self.table(item, "[geometry]")?;
        let mut mode = None;
        let (mut pivot, mut bearing, mut probes_given, mut forces) = (None, None, None, None);
        for (key, value) in table {
            match key.get_ref().as_ref() {
                "mode" => mode = Some((self.string(value, "geometry mode")?, value.span())),
                "pivot" => pivot = Some(self.number(value, "geometry pivot")?),
                "bearing" => bearing = Some(self.number(value, "geometry bearing")?),
                "probes" => probes_given = Some(self.numbers(value, "geometry probes")?),
                "forces" => forces = Some(self.numbers(value, "geometry forces")?),
                other => {
                    return Err(self.error(
                        key.span(),
                        format!(
                            "unknown key `{}` in [geometry]: expected mode, pivot, bearing, \
                             probes, forces",
                            excerpt(other)
                        ),
                    ));
                }
            }
        }
        let whole = item.span();
        let missing = |key: &str| self.error(whole.clone(), format!("[geometry] needs `{key}`"));
        let probes = |probes: Option<Vec<f64>>| probes.ok_or_else(|| missing("probes"));
        let bearing = bearing.ok_or_else(|| missing("bearing"))?;
        let geometry = match mode {
            Some(("conical", _)) => {
                let pivot = pivot.ok_or_else(|| missing("pivot"))?;
                Geometry::conical(pivot, bearing, probes(probes_given)?, forces)
            }
            Some(("two-plane", span)) => {
                if let Some((key, _)) = [("pivot", pivot.is_some()), ("forces", forces.is_some())]
                    .into_iter()
                    .find(|(_, given)| *given)
                {
                    return Err(self.error(
                        span,
                        format!(
                            "geometry mode `two-plane` takes no `{key}`: the motion is \
                             interpolated between the two planes, and the forces act at the \
                             bearing plane"
                        ),
                    ));
                }
                Geometry::two_plane(bearing, probes(probes_given)?)
            }
            Some((other, span)) => {
                return Err(self.error(
                    span,
                    format!(
                        "geometry mode `{}`: expected conical or two-plane",
                        excerpt(other)
                    ),
                ));
            }
            None => return Err(missing("mode")),
        };
        geometry.map_err(|e| match e {
            Error::InvalidParameter {
                name,
                value,
                expected,
            } => self.error(
                whole.clone(),
                format!("{name} = {value}: expected {expected}"),
            ),
            e => e,
        })
    }

    fn point(
        &self,
        item: &Item<'_>,
        conditions: &[Condition],
    ) -> Result<(Point, Option<(String, usize)>)> {
        let table = self.table(item, "[[point]]")?;
        let line = self.line(item.span());
        let mut name = None;
        let mut files = Vec::new();
        let mut baseline = None;
        let mut expect = Vec::new();
        let mut overrides = Vec::new();
        let mut values = vec![None; conditions.len()];
        for (key, value) in table {
            match key.get_ref().as_ref() {
                "name" => name = Some(self.string(value, "point name")?.to_owned()),
                "files" => {
                    files = match value.get_ref() {
                        DeValue::String(s) => vec![s.to_string()],
                        DeValue::Array(items) => items
                            .iter()
                            .map(|x| self.string(x, "files").map(str::to_owned))
                            .collect::<Result<_>>()?,
                        _ => {
                            return Err(self.error(
                                value.span(),
                                "files: expected a pattern or an array of patterns".into(),
                            ));
                        }
                    }
                }
                "baseline" => {
                    baseline = Some((
                        self.string(value, "baseline")?.to_owned(),
                        self.line(value.span()),
                    ));
                }
                "expect" => {
                    for (coefficient, pair) in self.table(value, "expect")? {
                        let c = Coefficient::parse(coefficient.get_ref()).ok_or_else(|| {
                            self.error(
                                coefficient.span(),
                                format!(
                                    "expect: `{}` is no coefficient; expected e.g. M_xx, K_xy, C_yy",
                                    excerpt(coefficient.get_ref())
                                ),
                            )
                        })?;
                        let v = self.numbers(pair, "expect")?;
                        let [reference, std] = v[..] else {
                            return Err(self.error(
                                pair.span(),
                                format!(
                                    "expect {}: expected [value, standard uncertainty]",
                                    c.name()
                                ),
                            ));
                        };
                        if !reference.is_finite() || !std.is_finite() || std < 0.0 {
                            return Err(self.error(
                                pair.span(),
                                format!(
                                    "expect {}: a finite value and a finite standard uncertainty ≥ 0",
                                    c.name()
                                ),
                            ));
                        }
                        expect.push(Expectation {
                            coefficient: c,
                            reference,
                            std,
                        });
                    }
                }
                "identify" => overrides = self.settings(self.table(value, "identify")?)?,
                other => {
                    let Some(i) = conditions.iter().position(|c| c.name == other) else {
                        return Err(self.error(
                            key.span(),
                            format!(
                                "unknown key `{}` in a point: expected {} or a condition ({})",
                                excerpt(other),
                                POINT_KEYS.join(", "),
                                conditions
                                    .iter()
                                    .map(|c| c.name.as_str())
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            ),
                        ));
                    };
                    values[i] = Some(match value.get_ref() {
                        DeValue::String(s) => Value::Text(s.to_string()),
                        _ => {
                            let x = self.number(value, other)?;
                            if !x.is_finite() {
                                return Err(self.error(
                                    value.span(),
                                    format!("{other}: expected a finite number"),
                                ));
                            }
                            Value::Number(x)
                        }
                    });
                }
            }
        }
        let name = name.ok_or_else(|| self.error(item.span(), "a point needs `name`".into()))?;
        if files.is_empty() {
            return Err(self.error(
                item.span(),
                format!("point `{}` needs `files`", excerpt(&name)),
            ));
        }
        Ok((
            Point {
                name,
                line,
                files,
                values,
                baseline: None,
                expect,
                overrides,
            },
            baseline,
        ))
    }
}

impl Plan {
    /// Reads the plan at `path` (file patterns are then relative to its folder).
    ///
    /// # Errors
    /// [`Error::Io`] if it cannot be read; [`Error::TooLarge`]-style limits as for the JSON
    /// readers; those of [`Plan::from_toml`].
    pub fn read(path: &Path) -> Result<Self> {
        let text = crate::limits::read_json_text(path)?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Self::from_toml(&text, &path.display().to_string(), base)
    }

    /// The plan in `text` (named `source` in errors), file patterns relative to `base`.
    ///
    /// # Errors
    /// [`Error::Plan`] (kind `invalid_input`) naming the line: TOML that does not parse, an
    /// unknown key, a value of the wrong type, a point without name or files, a duplicate
    /// point name, a baseline that names no point, a cycle of baselines, a geometry that is
    /// not well formed, an `expect` that is not `[value, std]`.
    ///
    /// # Examples
    /// ```
    /// use bearing_ident::campaign::Plan;
    /// let plan = Plan::from_toml(
    ///     "[identify]\nband = [8.0, 49.0]\n[conditions]\nspeed = \"rpm\"\n\
    ///      [[point]]\nname = \"dry\"\nfiles = [\"dry/*.csv\"]\nspeed = 0\n",
    ///     "plan.toml",
    ///     "study".into(),
    /// )?;
    /// assert_eq!(plan.points[0].name, "dry");
    /// assert_eq!(plan.shared[0].text, "8,49");
    /// let e = Plan::from_toml("[[point]]\nname = \"a\"\nfile = \"x\"\n", "p.toml", ".".into())
    ///     .unwrap_err();
    /// assert_eq!(e.kind(), "invalid_input");
    /// assert!(e.to_string().starts_with("p.toml:3: unknown key `file`"));
    /// # Ok::<(), bearing_ident::Error>(())
    /// ```
    pub fn from_toml(text: &str, source: &str, base: PathBuf) -> Result<Self> {
        let r = Reader {
            text,
            source: source.to_owned(),
        };
        let root = DeTable::parse(text).map_err(|e| {
            let at = e.span().map_or(0, |s| s.start);
            r.error(at..at, e.message().to_owned())
        })?;
        let mut shared = Vec::new();
        let mut conditions = Vec::new();
        let mut geometry = None;
        let mut point_items: Vec<&Item<'_>> = Vec::new();
        for (key, value) in root.get_ref() {
            match key.get_ref().as_ref() {
                "identify" => shared = r.settings(r.table(value, "[identify]")?)?,
                "conditions" => conditions = r.conditions(r.table(value, "[conditions]")?)?,
                "geometry" => geometry = Some(value),
                "point" => {
                    point_items = value
                        .get_ref()
                        .as_array()
                        .ok_or_else(|| {
                            r.error(value.span(), "point: expected [[point]] tables".into())
                        })?
                        .iter()
                        .collect();
                }
                other => {
                    return Err(r.error(
                        key.span(),
                        format!(
                            "unknown key `{}`: expected [identify], [conditions], [geometry], \
                             [[point]]",
                            excerpt(other)
                        ),
                    ));
                }
            }
        }
        let geometry_line = geometry.map_or(0, |g| r.line(g.span()));
        let geometry = geometry.map(|g| r.geometry(g)).transpose()?;
        if point_items.is_empty() {
            return Err(r.error(0..0, "the plan has no [[point]]".into()));
        }
        let mut points = Vec::with_capacity(point_items.len());
        let mut baselines = Vec::with_capacity(point_items.len());
        for item in point_items {
            let (point, baseline) = r.point(item, &conditions)?;
            if let Some(first) = points.iter().find(|p: &&Point| p.name == point.name) {
                return Err(r.error(
                    item.span(),
                    format!(
                        "duplicate point name `{}` (first at line {})",
                        excerpt(&point.name),
                        first.line
                    ),
                ));
            }
            points.push(point);
            baselines.push(baseline);
        }
        for (i, baseline) in baselines.into_iter().enumerate() {
            if let Some((name, line)) = baseline {
                let Some(j) = points.iter().position(|p| p.name == name) else {
                    return Err(Error::Plan {
                        file: r.source.clone(),
                        line,
                        message: format!("baseline `{}` names no point", excerpt(&name)),
                    });
                };
                points[i].baseline = Some(j);
            }
        }
        // A baseline chain that comes back to its start is a cycle (a point its own baseline
        // included): every chain is followed at most `points.len()` steps.
        for start in 0..points.len() {
            let mut at = points[start].baseline;
            for _ in 0..points.len() {
                match at {
                    Some(j) if j == start => {
                        return Err(Error::Plan {
                            file: r.source.clone(),
                            line: points[start].line,
                            message: format!(
                                "point `{}`: its baselines form a cycle",
                                excerpt(&points[start].name)
                            ),
                        });
                    }
                    Some(j) => at = points[j].baseline,
                    None => break,
                }
            }
        }
        let plan = Plan {
            source: r.source.clone(),
            base,
            shared,
            conditions,
            geometry,
            points,
        };
        // Every point's options and channels are checked now, so a run meets no plan fault.
        for point in &plan.points {
            let (_, channels) = plan.options_of(point)?;
            let named = plan.channels(&channels, &[]).map_err(|e| Error::Plan {
                file: plan.source.clone(),
                line: channels.first().map_or(point.line, |s| s.line),
                message: e.to_string(),
            })?;
            if let Some(g) = &plan.geometry {
                let n = named.csv.displacements.len();
                if g.probes().len() != n || g.forces().is_some_and(|f| f.len() != n) {
                    return Err(Error::Plan {
                        file: plan.source.clone(),
                        line: geometry_line,
                        message: format!(
                            "[geometry]: {} probes and {} force planes for point `{}`'s {n} \
                             response channels; give one per channel",
                            g.probes().len(),
                            g.forces().map_or(0, <[f64]>::len),
                            excerpt(&point.name)
                        ),
                    });
                }
            }
        }
        Ok(plan)
    }

    /// The options of `point`: the command's defaults, then the shared settings, then the
    /// point's own, in order; and its channel settings (name, text).
    ///
    /// # Errors
    /// [`Options::set`]'s, named with the plan's line; [`Error::Plan`] when no band is given.
    pub(super) fn options_of(&self, point: &Point) -> Result<(Options, Vec<Setting>)> {
        settings::options(&self.source, &self.shared, &self.conditions, point)
    }

    /// The channels of a point from its channel settings and the plan's geometry, for
    /// `files`.
    ///
    /// # Errors
    /// A response kind that does not parse; [`Channels::named`]'s.
    pub(super) fn channels(&self, given: &[Setting], files: &[PathBuf]) -> Result<Channels> {
        settings::channels(given, self.geometry.as_ref(), files)
    }

    /// The files of `point`: each pattern matched (relative to the plan's folder), in
    /// sorted order within a pattern, patterns in the order given.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] (`files`) for a pattern that does not parse or matches no
    /// file.
    pub(super) fn files(&self, point: &Point) -> Result<Vec<PathBuf>> {
        settings::files(&self.base, point)
    }

    /// The channels the point named `name` reads its files by (its channel settings and the
    /// plan's geometry).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for a name that is no point; the channel settings' errors.
    pub fn channels_of(&self, name: &str) -> Result<Channels> {
        let point =
            self.points
                .iter()
                .find(|p| p.name == name)
                .ok_or_else(|| Error::InvalidOption {
                    option: "point",
                    message: format!("no point `{}` in the plan", excerpt(name)),
                })?;
        let (_, given) = self.options_of(point)?;
        let files = self.files(point).unwrap_or_default();
        self.channels(&given, &files)
    }

    /// The geometry section of a `--geometry FILE.toml` for `identify`: the keys of a plan's
    /// `[geometry]` at the top level.
    ///
    /// # Errors
    /// [`Error::Io`]; [`Error::Plan`] naming the line of a fault.
    pub fn read_geometry(path: &Path) -> Result<Geometry> {
        let text = crate::limits::read_json_text(path)?;
        let r = Reader {
            text: &text,
            source: path.display().to_string(),
        };
        let root = DeTable::parse(&text).map_err(|e| {
            let at = e.span().map_or(0, |s| s.start);
            r.error(at..at, e.message().to_owned())
        })?;
        let table = Spanned::new(0..text.len(), DeValue::Table(root.into_inner()));
        r.geometry(&table)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        Plan::from_toml(text, "p.toml", ".".into())
            .unwrap_err()
            .to_string()
    }

    /// `mode = "two-plane"`: the probes read, two per direction; a pivot or force planes, an
    /// odd count, coincident planes or a response count that does not fit are faults naming
    /// the key or the line.
    #[test]
    fn two_plane_geometry_is_read_and_checked() {
        let geometry = "[identify]\nband = [8.0, 49.0]\ndisp = [\"x1\", \"y1\", \"x2\", \"y2\"]\n\
                        [geometry]\nmode = \"two-plane\"\nbearing = 0.151\n";
        let point = "[[point]]\nname = \"a\"\nfiles = \"x\"\n";
        let plan = |extra: &str| format!("{geometry}{extra}\n{point}");
        let ok = Plan::from_toml(
            &plan("probes = [0.213, 0.213, 0.254, 0.254]"),
            "p.toml",
            ".".into(),
        )
        .unwrap();
        let g = ok.geometry.unwrap();
        assert!(g.is_two_plane());
        assert_eq!(g.probes(), [0.213, 0.213, 0.254, 0.254]);
        let e = err(&plan("probes = [0.213, 0.213, 0.254, 0.254]\npivot = 0.0"));
        assert!(
            e.starts_with("p.toml:5:") && e.contains("no `pivot`"),
            "{e}"
        );
        let e = err(&plan(
            "probes = [0.213, 0.213, 0.254, 0.254]\nforces = [0.1, 0.1]",
        ));
        assert!(e.contains("no `forces`"), "{e}");
        let e = err(&plan("probes = [0.213, 0.254, 0.3]"));
        assert!(e.contains("geometry probes = 3"), "{e}");
        let e = err(&plan("probes = [0.213, 0.2, 0.213, 0.3]"));
        assert!(
            e.contains("geometry probes = 0.213") && e.contains("distinct"),
            "{e}"
        );
        let e = err(&plan("probes = [0.2, 0.3]"));
        assert!(
            e.contains("2 probes") && e.contains("4 response channels"),
            "{e}"
        );
        assert!(err(&plan("")).contains("needs `probes`"));
        assert!(
            err(&format!(
                "{}\nprobes = [0.2, 0.3]\n{point}",
                geometry.replace("two-plane", "three-plane")
            ))
            .contains("expected conical or two-plane")
        );
    }

    /// Every fault of a plan is named with its line.
    #[test]
    fn faults_name_their_line() {
        let point = "[[point]]\nname = \"a\"\nfiles = \"a/*.csv\"\n";
        assert!(err("[identify]\nbnad = [1, 2]\n").starts_with("p.toml:2: unknown option `bnad`"));
        assert!(
            err(&format!("{point}[[point]]\nname = \"a\"\nfiles = \"b\"\n"))
                .starts_with("p.toml:4: duplicate point name `a` (first at line 1)")
        );
        assert!(
            err(&format!("{point}baseline = \"dry\"\n"))
                .starts_with("p.toml:4: baseline `dry` names no point")
        );
        assert!(err(&format!("{point}baseline = \"a\"\n")).contains("cycle"));
        let cycle = "[[point]]\nname = \"a\"\nfiles = \"x\"\nbaseline = \"b\"\n\
                     [[point]]\nname = \"b\"\nfiles = \"y\"\nbaseline = \"a\"\n";
        assert!(err(cycle).starts_with("p.toml:1: point `a`: its baselines form a cycle"));
        assert!(err("[conditions]\nspeed = \"rpm\"\n[[point]]\nname = \"a\"\nfiles = \"x\"\nspeed = \"fast\"\nload = 3\n")
            .starts_with("p.toml:7: unknown key `load` in a point"));
        assert!(err("[geometry]\nmode = \"conical\"\npivot = 0.0\nbearing = 0.1\nprobes = [0.0]\n[[point]]\nname = \"a\"\nfiles = \"x\"\n")
            .contains("geometry probes = 0"));
        assert!(
            err(&format!("{point}[point.expect]\nM_xx = [4.0]\n"))
                .starts_with("p.toml:5: expect M_xx: expected [value, standard uncertainty]")
        );
        assert!(err("[identify\nband = 3\n").starts_with("p.toml:1:"));
        let three = "[identify]\nband = [8.0, 49.0]\n[geometry]\nmode = \"conical\"\npivot = 0.0\n\
                     bearing = 0.1\nprobes = [0.2, 0.3, 0.4]\n[[point]]\nname = \"a\"\nfiles = \"x\"\n";
        let e = err(three);
        assert!(
            e.starts_with("p.toml:") && e.contains("3 probes and 0 force planes"),
            "{e}"
        );
        assert!(err("").contains("no [[point]]"));
        assert!(err("[[point]]\nfiles = \"x\"\n").starts_with("p.toml:1: a point needs `name`"));
    }

    /// A full plan reads back with its conditions in order, its overrides and references.
    #[test]
    fn a_plan_reads_back() {
        let plan = Plan::from_toml(
            r#"
[identify]
band = [8.0, 49.0]
method = "ivf"
reject_bad_records = true
delay = "force=0.25ms±0.02ms"
[conditions]
speed = "rpm"
air_fraction = "1"
[geometry]
mode = "conical"
pivot = 0.0
bearing = 0.151
probes = [0.213, 0.254]
[[point]]
name = "dry"
files = ["dry/*.csv"]
speed = 0
air_fraction = 1.0
[point.expect]
M_xx = [4.02, 0.1]
K_xx = [150e3, 5e3]
[[point]]
name = "oil-3000"
files = ["oil_3000/*.csv"]
speed = 3000
air_fraction = 0.0
baseline = "dry"
identify = { band = [10.0, 45.0], highpass = "response=3Hz" }
"#,
            "p.toml",
            "study".into(),
        )
        .unwrap();
        assert_eq!(plan.conditions[0].name, "speed");
        assert_eq!(plan.conditions[1].unit, Unit::Other("1".into()));
        assert_eq!(plan.shared[2].name, "reject-bad-records");
        assert_eq!(plan.shared[2].text, "true");
        assert_eq!(plan.points[1].baseline, Some(0));
        assert_eq!(plan.points[1].values[0], Some(Value::Number(3000.0)));
        assert_eq!(plan.points[1].overrides[0].text, "10,45");
        // The channels' known delays and AC coupling, as `--delay`/`--highpass` take them.
        assert_eq!(plan.shared[3].name, "delay");
        assert_eq!(plan.shared[3].text, "force=0.25ms±0.02ms");
        assert_eq!(plan.points[1].overrides[1].name, "highpass");
        assert_eq!(
            plan.points[0].expect[1].reference.to_bits(),
            150e3_f64.to_bits()
        );
        assert_eq!(plan.points[0].line, 15); // its `[[point]]` header
        assert_eq!(plan.geometry.unwrap().probes(), [0.213, 0.254]);
    }
}
