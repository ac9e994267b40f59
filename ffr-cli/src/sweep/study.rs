//! The study file (TOML): a scene, its parameter axes and the figures to
//! collect per case, read with serde and `toml::Spanned` so that every
//! error names `file:line:col` (as scene files do).
//!
//! ```toml
//! scene = "spin_up.toml"                  # relative to the study file
//! [axes]                                  # the cases: the product of the axes
//! "joints.0.drive.omega" = [2.0, 4.0]     # a list
//! "bodies.beam.elements" = { from = 4, to = 16, step = 4 }          # integers
//! "bodies.beam.params.e" = { from = 6e10, to = 8e10, steps = 5 }    # numbers, ends included
//! "t_end" = { uniform = [1.0, 2.0], samples = 3, seed = 1 }         # seeded samples
//! [collect]
//! tip_min = { output = "tip_transverse", stat = "min" }
//! tip_err = { output = "tip_transverse", stat = "max_error", reference = "ref.csv", column = "tip_transverse" }
//! ```

use super::cases::{Axis, MAX_CASES};
use super::collect::{Figure, Stat};
use crate::reference::Reference;
use ffr::runtime::spec::Location;
use ffr::scene::{SceneText, SceneValue};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use toml::Spanned;

/// The most axes a study may have.
pub const MAX_AXES: usize = 32;
/// The most figures a study may collect.
pub const MAX_FIGURES: usize = 64;
/// The most bytes a study file may have.
pub const MAX_STUDY_BYTES: u64 = 1 << 20;
/// The longest figure name, in bytes.
pub const MAX_NAME_LEN: usize = 64;
/// The most characters of a message about a study (longer ones are cut
/// with `…`; the user text in them is cut shorter).
pub const MAX_MESSAGE_CHARS: usize = 2000;

/// Columns of `results.csv` besides the axes and the figures.
pub const FIXED_COLUMNS: [&str; 4] = ["case", "cpu_s", "status", "message"];

/// A study error: where in which file, and what.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyError {
    /// `file:line:col` when the problem has a place in the study file.
    pub location: Option<Location>,
    /// What is wrong.
    pub message: String,
}

impl std::fmt::Display for StudyError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.location {
            Some(l) => write!(f, "{l}: {}", self.message),
            None => write!(f, "{}", self.message),
        }
    }
}

impl std::error::Error for StudyError {}

/// A study, read and checked: its scene (parsed once, cloned per case),
/// axes in the order the file gives them and figures likewise.
#[derive(Clone, Debug)]
pub struct Study {
    /// The study file as given.
    pub path: PathBuf,
    /// The scene file (relative to the study file's directory).
    pub scene_path: PathBuf,
    /// The scene's text, to which each case sets its axes' values.
    pub scene: SceneText,
    /// The axes, in file order; the cases are their product (the last axis
    /// varies fastest).
    pub axes: Vec<Axis>,
    /// The figures, in file order.
    pub figures: Vec<Figure>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStudy {
    scene: Spanned<String>,
    #[serde(default)]
    axes: BTreeMap<Spanned<String>, Spanned<RawAxis>>,
    #[serde(default)]
    collect: BTreeMap<Spanned<String>, Spanned<RawFigure>>,
}

/// A list of values, or a table (a range or seeded samples).
#[derive(Debug)]
enum RawAxis {
    List(Vec<Spanned<toml::Value>>),
    Table(Box<RawAxisTable>),
}

impl<'de> Deserialize<'de> for RawAxis {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = RawAxis;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a list of values ([2.0, 4.0]), a range ({ from = 1.0, to = 4.0, steps = 7 } or { from = 4, to = 16, step = 4 }) or seeded samples ({ uniform = [1.0, 2.0], samples = 20, seed = 1 })")
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<RawAxis, A::Error> {
                let mut out = Vec::new();
                while let Some(v) = seq.next_element::<Spanned<toml::Value>>()? {
                    if out.len() >= MAX_CASES {
                        return Err(serde::de::Error::custom(format!(
                            "more than {MAX_CASES} values (MAX_CASES)"
                        )));
                    }
                    out.push(v);
                }
                Ok(RawAxis::List(out))
            }
            // Read by the TOML deserializer itself: the fields keep their spans.
            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<RawAxis, A::Error> {
                RawAxisTable::deserialize(serde::de::value::MapAccessDeserializer::new(map))
                    .map(|t| RawAxis::Table(Box::new(t)))
            }
        }
        d.deserialize_any(V)
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawAxisTable {
    from: Option<Spanned<toml::Value>>,
    to: Option<Spanned<toml::Value>>,
    steps: Option<Spanned<i64>>,
    step: Option<Spanned<i64>>,
    uniform: Option<Spanned<Vec<f64>>>,
    normal: Option<Spanned<Vec<f64>>>,
    samples: Option<Spanned<i64>>,
    seed: Option<Spanned<i64>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFigure {
    output: Spanned<String>,
    stat: Spanned<String>,
    reference: Option<Spanned<String>>,
    column: Option<Spanned<String>>,
}

/// Reads one study file, locating errors in it.
struct Reader<'a> {
    file: String,
    text: &'a str,
}

impl Reader<'_> {
    /// An error at `span`; its message escaped and cut
    /// ([`MAX_MESSAGE_CHARS`]), whatever user text it quotes.
    fn err(&self, span: Range<usize>, message: impl Into<String>) -> StudyError {
        StudyError {
            location: Some(Location::of(&self.file, self.text, span.start)),
            message: ffr::codegen::sanitize::snippet(&message.into(), MAX_MESSAGE_CHARS),
        }
    }
}

/// How two axis keys' places overlap.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Overlap {
    /// The same place (`joints.0` and `joints.00`).
    Same,
    /// The second inside the first (`joints.0.drive`, `joints.0.drive.omega`).
    Inside,
    /// The first inside the second.
    Holds,
}

/// Whether keys `a` and `b` reach overlapping places: segments compared as
/// [`SceneText::set`] reads them, an index by its number (`00` is `0`).
fn overlap(a: &str, b: &str) -> Option<Overlap> {
    fn segment(s: &str) -> &str {
        if !s.is_empty() && s.bytes().all(|c| c.is_ascii_digit()) {
            let t = s.trim_start_matches('0');
            if t.is_empty() {
                "0"
            } else {
                t
            }
        } else {
            s
        }
    }
    let sa: Vec<&str> = a.split('.').map(segment).collect();
    let sb: Vec<&str> = b.split('.').map(segment).collect();
    let common = sa.len().min(sb.len());
    if sa[..common] != sb[..common] {
        return None;
    }
    Some(match sa.len().cmp(&sb.len()) {
        std::cmp::Ordering::Equal => Overlap::Same,
        std::cmp::Ordering::Less => Overlap::Inside,
        std::cmp::Ordering::Greater => Overlap::Holds,
    })
}

fn quoted(s: &str) -> String {
    ffr::codegen::sanitize::snippet(s, 80)
}

/// Read and check a study file: its TOML, the scene it names (read and
/// parsed; each case's scene is checked when the case runs), the axes
/// (keys that exist in the scene, values, at most [`MAX_CASES`] cases),
/// the figures (outputs of the scene, statistics, reference files).
pub fn read(path: &Path) -> Result<Study, StudyError> {
    let plain = |message: String| StudyError {
        location: None,
        message,
    };
    let file = ffr::codegen::sanitize::snippet(&path.display().to_string(), usize::MAX);
    let bytes =
        ffr::codegen::limits::read_input(path, MAX_STUDY_BYTES, "study file", "MAX_STUDY_BYTES")
            .map_err(|m| plain(format!("{file}: {m}")))?;
    let text = String::from_utf8(bytes).map_err(|e| {
        plain(format!(
            "{file}: is not UTF-8 text (byte offset {})",
            e.utf8_error().valid_up_to()
        ))
    })?;
    let r = Reader { file, text: &text };
    let raw: RawStudy = toml::from_str(&text).map_err(|e| {
        let offset = e.span().map_or(0, |s| s.start);
        let msg = e.message().trim().to_string();
        StudyError {
            location: Some(Location::of(&r.file, &text, offset)),
            message: if msg.is_empty() {
                "the file is not valid TOML".into()
            } else {
                ffr::codegen::sanitize::snippet(&msg, 1024)
            },
        }
    })?;
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    // The scene, relative to the study file.
    let scene_rel = raw.scene.get_ref();
    if scene_rel.trim().is_empty() {
        return Err(r.err(
            raw.scene.span(),
            "`scene` is empty: name the scene file (relative to the study file)",
        ));
    }
    let scene_path = base.join(scene_rel);
    let scene = SceneText::read(&scene_path).map_err(|e| {
        r.err(
            raw.scene.span(),
            format!("scene `{}`: {e}", quoted(scene_rel)),
        )
    })?;

    // Axes in file order (serde's map is sorted by key; the spans give the order).
    let mut raw_axes: Vec<_> = raw.axes.into_iter().collect();
    raw_axes.sort_by_key(|(k, _)| k.span().start);
    if raw_axes.len() > MAX_AXES {
        return Err(r.err(
            raw_axes[MAX_AXES].0.span(),
            format!("more than {MAX_AXES} axes (MAX_AXES)"),
        ));
    }
    let mut axes = Vec::new();
    let mut cases: usize = 1;
    for (key, axis) in &raw_axes {
        let values = axis_values(&r, axis)?;
        if values.is_empty() {
            return Err(r.err(
                axis.span(),
                format!("axis `{}` has no values", quoted(key.get_ref())),
            ));
        }
        // Two axes on one place (the same key, or one inside the other)
        // would make rows report values the run did not use.
        if let Some((other, _)) = raw_axes
            .iter()
            .take_while(|(k, _)| k.span() != key.span())
            .find(|(k, _)| overlap(k.get_ref(), key.get_ref()).is_some())
        {
            let line = text[..other.span().start].matches('\n').count() + 1;
            let how = match overlap(other.get_ref(), key.get_ref()) {
                Some(Overlap::Same) => "sets the same place as",
                Some(Overlap::Inside) => "sets a value inside the place of",
                _ => "sets the place holding",
            };
            return Err(r.err(
                key.span(),
                format!(
                    "axis `{}` {how} axis `{}` (line {line}): a row would report a value the run did not use; keep one of them",
                    quoted(key.get_ref()),
                    quoted(other.get_ref())
                ),
            ));
        }
        // The key must reach a place in the scene (set checks the path).
        let mut probe = scene.clone();
        probe.set(key.get_ref(), values[0].clone()).map_err(|e| {
            r.err(
                key.span(),
                format!("axis `{}`: {}", quoted(key.get_ref()), e.message),
            )
        })?;
        cases = cases
            .checked_mul(values.len())
            .filter(|&n| n <= MAX_CASES)
            .ok_or_else(|| {
                r.err(
                    key.span(),
                    format!(
                        "the axes give more than {MAX_CASES} cases (MAX_CASES); split the study"
                    ),
                )
            })?;
        axes.push(Axis {
            key: key.get_ref().clone(),
            values,
        });
    }

    // Figures in file order, against the scene's outputs.
    let outputs: Vec<String> = match scene.spec() {
        Ok(spec) => spec.outputs.iter().map(|o| o.name.clone()).collect(),
        Err(e) => {
            return Err(r.err(
                raw.scene.span(),
                format!("scene `{}`: {e}", quoted(scene_rel)),
            ))
        }
    };
    let mut raw_figs: Vec<_> = raw.collect.into_iter().collect();
    raw_figs.sort_by_key(|(k, _)| k.span().start);
    if raw_figs.len() > MAX_FIGURES {
        return Err(r.err(
            raw_figs[MAX_FIGURES].0.span(),
            format!("more than {MAX_FIGURES} figures (MAX_FIGURES)"),
        ));
    }
    // The figures, checked; their references are read afterwards, each
    // file once with every column the study's figures take from it.
    struct Wants {
        path: PathBuf,
        column: String,
        file_span: Range<usize>,
        column_span: Option<Range<usize>>,
    }
    let mut pending: Vec<(Figure, Option<Wants>)> = Vec::new();
    for (name, fig) in &raw_figs {
        let n = name.get_ref();
        let bad_name = n.is_empty()
            || n.len() > MAX_NAME_LEN
            || !n
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'));
        if bad_name {
            return Err(r.err(name.span(), format!("figure name `{}`: use 1 to {MAX_NAME_LEN} letters, digits, `_`, `-` or `.` (it is a CSV column)", quoted(n))));
        }
        if FIXED_COLUMNS.contains(&n.as_str()) || axes.iter().any(|a| &a.key == n) {
            return Err(r.err(name.span(), format!("figure name `{n}` is already a column of results.csv (case, the axes' keys, cpu_s, status, message)")));
        }
        let f = fig.get_ref();
        let output = f.output.get_ref();
        if !outputs.contains(output) {
            return Err(r.err(
                f.output.span(),
                format!(
                    "the scene has no output `{}` (outputs: {})",
                    quoted(output),
                    if outputs.is_empty() {
                        "none".into()
                    } else {
                        outputs.join(", ")
                    }
                ),
            ));
        }
        let stat = Stat::from_name(f.stat.get_ref()).ok_or_else(|| {
            r.err(
                f.stat.span(),
                format!(
                    "unknown statistic `{}` (statistics: {})",
                    quoted(f.stat.get_ref()),
                    Stat::NAMES.join(", ")
                ),
            )
        })?;
        let wants = match (stat.needs_reference(), &f.reference, &f.column) {
            (true, Some(file), column) => Some(Wants {
                path: base.join(file.get_ref()),
                column: column
                    .as_ref()
                    .map_or(output.as_str(), |c| c.get_ref().as_str())
                    .to_string(),
                file_span: file.span(),
                column_span: column.as_ref().map(|c| c.span()),
            }),
            (true, None, _) => {
                return Err(r.err(fig.span(), format!("`{}` needs `reference = \"FILE.csv\"` (relative to the study file; optional `column`, default the output's name)", stat.name())))
            }
            (false, Some(x), _) => {
                return Err(r.err(x.span(), format!("`reference` goes with max_error or max_abs_error, not {}", stat.name())))
            }
            (false, None, Some(x)) => {
                return Err(r.err(x.span(), format!("`column` goes with max_error or max_abs_error, not {}", stat.name())))
            }
            (false, None, None) => None,
        };
        pending.push((
            Figure {
                name: n.clone(),
                output: output.clone(),
                stat,
                reference: None,
            },
            wants,
        ));
    }
    // Each reference file once, with the columns wanted from it, the
    // numbers of all of them bounded together (MAX_REFERENCE_VALUES).
    let mut references: BTreeMap<PathBuf, Arc<Reference>> = BTreeMap::new();
    let mut held = 0usize;
    for k in 0..pending.len() {
        let Some(w) = &pending[k].1 else { continue };
        let reference = match references.get(&w.path) {
            Some(x) => x.clone(),
            None => {
                let columns: Vec<&str> = pending
                    .iter()
                    .filter_map(|(_, o)| o.as_ref())
                    .filter(|o| o.path == w.path)
                    .map(|o| o.column.as_str())
                    .collect();
                let mut x = Reference::read_columns(&w.path, Some(&columns), held)
                    .map_err(|e| r.err(w.file_span.clone(), e))?;
                held += x.numbers();
                // Every missing column is an error at its figure.
                if let Some(o) = pending[k..]
                    .iter()
                    .filter_map(|(_, o)| o.as_ref())
                    .find(|o| o.path == w.path && x.column(&o.column).is_none())
                {
                    let shown: Vec<String> = x.header.iter().take(20).map(|c| quoted(c)).collect();
                    let more = x.header.len().saturating_sub(shown.len());
                    return Err(r.err(
                        o.column_span.clone().unwrap_or(o.file_span.clone()),
                        format!(
                            "the reference has no column `{}` (columns: {}{})",
                            quoted(&o.column),
                            shown.join(", "),
                            if more > 0 {
                                format!(" and {more} more")
                            } else {
                                String::new()
                            }
                        ),
                    ));
                }
                x.header = Vec::new();
                let x = Arc::new(x);
                references.insert(w.path.clone(), x.clone());
                x
            }
        };
        let column = w.column.clone();
        pending[k].0.reference = Some((reference, column));
    }
    let figures = pending.into_iter().map(|(f, _)| f).collect();
    Ok(Study {
        path: path.to_path_buf(),
        scene_path,
        scene,
        axes,
        figures,
    })
}

/// A TOML value as a scene value (numbers finite; no dates).
fn scene_value(r: &Reader, v: &toml::Value, span: Range<usize>) -> Result<SceneValue, StudyError> {
    Ok(match v {
        toml::Value::Boolean(b) => SceneValue::Bool(*b),
        toml::Value::Integer(i) => SceneValue::Int(*i),
        toml::Value::Float(x) if x.is_finite() => SceneValue::Float(*x),
        toml::Value::Float(x) => return Err(r.err(span, format!("{x} is not a finite number"))),
        toml::Value::String(s) => SceneValue::Str(s.clone()),
        toml::Value::Array(a) => SceneValue::Array(
            a.iter()
                .map(|x| scene_value(r, x, span.clone()))
                .collect::<Result<_, _>>()?,
        ),
        toml::Value::Table(t) => SceneValue::Table(
            t.iter()
                .map(|(k, x)| Ok((k.clone(), scene_value(r, x, span.clone())?)))
                .collect::<Result<_, StudyError>>()?,
        ),
        toml::Value::Datetime(_) => return Err(r.err(span, "a date is not a scene value")),
    })
}

fn number(r: &Reader, v: &Spanned<toml::Value>, what: &str) -> Result<f64, StudyError> {
    match v.get_ref() {
        toml::Value::Integer(i) => Ok(*i as f64),
        toml::Value::Float(x) if x.is_finite() => Ok(*x),
        _ => Err(r.err(v.span(), format!("`{what}` must be a finite number"))),
    }
}

fn count(r: &Reader, v: &Spanned<i64>, what: &str) -> Result<usize, StudyError> {
    let n = *v.get_ref();
    if n < 1 || n as u64 > MAX_CASES as u64 {
        return Err(r.err(
            v.span(),
            format!("`{what}` must be from 1 to {MAX_CASES} (MAX_CASES), not {n}"),
        ));
    }
    Ok(n as usize)
}

/// Sampled or ranged values as scene values, each a finite number (a
/// normal sample far out in the tail of a huge `sd` is not).
fn finite(
    r: &Reader,
    values: Vec<f64>,
    what: &str,
    span: Range<usize>,
) -> Result<Vec<SceneValue>, StudyError> {
    if let Some((k, x)) = values.iter().enumerate().find(|(_, x)| !x.is_finite()) {
        return Err(r.err(
            span,
            format!("`{what}`: value {k} is {x}, not a finite number; give smaller numbers"),
        ));
    }
    Ok(values.into_iter().map(SceneValue::Float).collect())
}

/// The values of one axis.
fn axis_values(r: &Reader, axis: &Spanned<RawAxis>) -> Result<Vec<SceneValue>, StudyError> {
    let t = match axis.get_ref() {
        RawAxis::List(items) => {
            return items
                .iter()
                .map(|v| scene_value(r, v.get_ref(), v.span()))
                .collect();
        }
        RawAxis::Table(t) => t,
    };
    let span = axis.span();
    let range = t.from.is_some() || t.to.is_some() || t.steps.is_some() || t.step.is_some();
    let sampled =
        t.uniform.is_some() || t.normal.is_some() || t.samples.is_some() || t.seed.is_some();
    if range && sampled {
        return Err(r.err(span, "an axis is a range (from, to, steps or step) or samples (uniform or normal, samples, seed), not both"));
    }
    if range {
        let (Some(from), Some(to)) = (&t.from, &t.to) else {
            return Err(r.err(span, "a range needs `from` and `to`, and `steps` (numbers, ends included) or `step` (integers)"));
        };
        return match (&t.steps, &t.step) {
            (Some(steps), None) => {
                let (a, b) = (number(r, from, "from")?, number(r, to, "to")?);
                let n = count(r, steps, "steps")?;
                if n == 1 && a != b {
                    return Err(r.err(steps.span(), "one step needs from = to"));
                }
                finite(r, super::cases::linspace(a, b, n), "from, to, steps", span.clone())
            }
            (None, Some(step)) => {
                let int = |v: &Spanned<toml::Value>, what: &str| match v.get_ref() {
                    toml::Value::Integer(i) => Ok(*i),
                    _ => Err(r.err(v.span(), format!("`{what}` must be an integer with `step` (give `steps` for numbers)"))),
                };
                let (a, b, s) = (int(from, "from")?, int(to, "to")?, *step.get_ref());
                if s < 1 {
                    return Err(r.err(step.span(), "`step` must be a positive integer"));
                }
                if b < a {
                    return Err(r.err(to.span(), "`to` must not be below `from`"));
                }
                let n = ((b as i128 - a as i128) / s as i128 + 1) as u128;
                if n > MAX_CASES as u128 {
                    return Err(r.err(step.span(), format!("the range has more than {MAX_CASES} values (MAX_CASES)")));
                }
                // In i128: `i s` may pass i64 though every value, at most
                // `to`, fits.
                Ok((0..n as i128)
                    .map(|i| SceneValue::Int((a as i128 + i * s as i128) as i64))
                    .collect())
            }
            _ => Err(r.err(span, "a range needs exactly one of `steps` (numbers, ends included) and `step` (integers)")),
        };
    }
    if sampled {
        let (Some(samples), Some(seed)) = (&t.samples, &t.seed) else {
            return Err(r.err(
                span,
                "samples need `samples = N` and `seed = S` (the seed makes them reproducible)",
            ));
        };
        let n = count(r, samples, "samples")?;
        let s = *seed.get_ref();
        if s < 0 {
            return Err(r.err(seed.span(), "`seed` must be a non-negative integer"));
        }
        let pair = |v: &Spanned<Vec<f64>>, what: &str| -> Result<(f64, f64), StudyError> {
            match v.get_ref().as_slice() {
                [a, b] if a.is_finite() && b.is_finite() => Ok((*a, *b)),
                _ => Err(r.err(v.span(), format!("`{what}` takes two finite numbers"))),
            }
        };
        let (values, what, at) =
            match (&t.uniform, &t.normal) {
                (Some(u), None) => {
                    let (a, b) = pair(u, "uniform = [low, high]")?;
                    if !(a < b) {
                        return Err(r.err(u.span(), "`uniform = [low, high]` needs low < high"));
                    }
                    let v = super::cases::uniform(a, b, n, s as u64)
                        .map_err(|e| r.err(u.span(), format!("`uniform = [low, high]`: {e}")))?;
                    (v, "uniform = [low, high]", u.span())
                }
                (None, Some(g)) => {
                    let (m, sd) = pair(g, "normal = [mean, sd]")?;
                    if !(sd >= 0.0) {
                        return Err(r.err(g.span(), "`normal = [mean, sd]` needs sd ≥ 0"));
                    }
                    let v = super::cases::normal(m, sd, n, s as u64)
                        .map_err(|e| r.err(g.span(), format!("`normal = [mean, sd]`: {e}")))?;
                    (v, "normal = [mean, sd]", g.span())
                }
                _ => return Err(r.err(
                    span,
                    "samples need exactly one of `uniform = [low, high]` and `normal = [mean, sd]`",
                )),
            };
        return finite(r, values, what, at);
    }
    Err(r.err(
        span,
        "an empty table is not an axis: give a list, a range or samples",
    ))
}
