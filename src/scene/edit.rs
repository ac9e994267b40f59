//! Scene variants by dotted keys: a scene file's text with values set at
//! dotted paths, then resolved and built by the loader with its own located
//! errors. The one home for scene overrides (`ffr sweep`'s axes, the Python
//! package's `Scene.set`).
//!
//! A key names a value the way the file nests it: tables by name, arrays of
//! tables and arrays by a 0-based index, inline tables like tables
//! (`bodies.beam.params.e`, `joints.0.drive.omega`, `t_end`). Every segment
//! but the last must exist; the last may be new (a key the file leaves at
//! its default). A value may change its kind: a marker string replaced by
//! a marker table (`joints.0.a` = `{ at = "…", axes = { angle = … } }`)
//! and back, a point force given a `profile` table whose keys are then set
//! one by one (`forces.0.profile.table`). The edit keeps the file's layout and comments, and a
//! replaced value keeps its place, so the loader's `file:line:col` still
//! points into the file the user wrote.

use crate::scene::model::Scene;
use crate::scene::provider::{DefaultKernels, KernelProvider};
use crate::scene::SceneSpec;
use crate::SceneError;
use std::fmt;
use std::path::{Path, PathBuf};
use toml_edit::{DocumentMut, Item, Value};

/// The longest key [`SceneText::set`] takes, in bytes.
pub const MAX_KEY_LEN: usize = 512;

/// The deepest nesting of arrays and tables in a value [`SceneText::set`]
/// takes (a scene's values nest two or three deep).
pub const MAX_VALUE_DEPTH: usize = 32;

/// The most distinct keys set on one [`SceneText`] (a key set again
/// replaces its earlier value; a study's axes are at most 32).
pub const MAX_OVERRIDES: usize = 256;

/// The most keys set that an error message lists (then `and N more`).
const MAX_LISTED: usize = 8;

/// The most names of a table's or array's entries an error message lists.
const MAX_NAMES: usize = 16;

/// A value to set at a dotted key.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneValue {
    /// `true` / `false`.
    Bool(bool),
    /// An integer (element counts, indices).
    Int(i64),
    /// A finite number.
    Float(f64),
    /// A string (a shape name, a file, a marker).
    Str(String),
    /// An array (`position = [0.0, 1.0]`).
    Array(Vec<SceneValue>),
    /// An inline table (`drive = { angle = "spin-up", omega = 4.0 }`), keys in order.
    Table(Vec<(String, SceneValue)>),
}

impl fmt::Display for SceneValue {
    /// The value as TOML writes it (floats with the digits that read back
    /// to the same `f64`).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.to_toml() {
            Ok(v) => write!(f, "{}", v.to_string().trim()),
            Err(e) => write!(f, "<{e}>"),
        }
    }
}

impl SceneValue {
    fn to_toml(&self) -> Result<Value, String> {
        self.to_toml_at(0)
    }

    fn to_toml_at(&self, depth: usize) -> Result<Value, String> {
        if depth > MAX_VALUE_DEPTH {
            return Err(format!(
                "a value nested more than {MAX_VALUE_DEPTH} arrays or tables deep"
            ));
        }
        Ok(match self {
            SceneValue::Bool(b) => Value::from(*b),
            SceneValue::Int(i) => Value::from(*i),
            SceneValue::Float(x) => {
                if !x.is_finite() {
                    return Err(format!("{x} is not a finite number"));
                }
                Value::from(*x)
            }
            SceneValue::Str(s) => Value::from(s.as_str()),
            SceneValue::Array(items) => {
                let mut a = toml_edit::Array::new();
                for item in items {
                    a.push(item.to_toml_at(depth + 1)?);
                }
                Value::Array(a)
            }
            SceneValue::Table(entries) => {
                let mut t = toml_edit::InlineTable::new();
                for (k, v) in entries {
                    if t.contains_key(k) {
                        return Err(format!("key `{k}` twice in one table"));
                    }
                    t.insert(k, v.to_toml_at(depth + 1)?);
                }
                Value::InlineTable(t)
            }
        })
    }

    fn from_toml(v: &Value) -> Option<SceneValue> {
        Some(match v {
            Value::Boolean(b) => SceneValue::Bool(*b.value()),
            Value::Integer(i) => SceneValue::Int(*i.value()),
            Value::Float(x) => SceneValue::Float(*x.value()),
            Value::String(s) => SceneValue::Str(s.value().clone()),
            Value::Array(a) => {
                SceneValue::Array(a.iter().map(SceneValue::from_toml).collect::<Option<_>>()?)
            }
            Value::InlineTable(t) => SceneValue::Table(
                t.iter()
                    .map(|(k, v)| Some((k.to_string(), SceneValue::from_toml(v)?)))
                    .collect::<Option<_>>()?,
            ),
            Value::Datetime(_) => return None,
        })
    }
}

impl From<f64> for SceneValue {
    fn from(x: f64) -> Self {
        SceneValue::Float(x)
    }
}
impl From<i64> for SceneValue {
    fn from(i: i64) -> Self {
        SceneValue::Int(i)
    }
}
impl From<bool> for SceneValue {
    fn from(b: bool) -> Self {
        SceneValue::Bool(b)
    }
}
impl From<&str> for SceneValue {
    fn from(s: &str) -> Self {
        SceneValue::Str(s.to_string())
    }
}

/// A scene file's text with the values set so far, ready to load.
#[derive(Clone, Debug)]
pub struct SceneText {
    doc: DocumentMut,
    file: String,
    base: PathBuf,
    set: Vec<(String, SceneValue)>,
    /// The place each key of `set` names: its segments, an index as its
    /// number (`joints.00` and `joints.0` are one place).
    places: Vec<String>,
}

impl SceneText {
    /// Read a scene file (relative shape paths against its directory).
    pub fn read(path: &Path) -> crate::Result<SceneText> {
        let text = crate::codegen::scene::read(path)?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Ok(SceneText::parse(&text, &path.display().to_string(), &base)?)
    }

    /// A scene from its text; `file` names it in errors, `base` resolves
    /// relative paths. TOML syntax errors are located here; the scene's
    /// own checks run at [`SceneText::spec`] / [`SceneText::load`].
    pub fn parse(text: &str, file: &str, base: &Path) -> Result<SceneText, SceneError> {
        let doc: DocumentMut = text.parse().map_err(|e: toml_edit::TomlError| SceneError {
            location: Some(crate::runtime::spec::Location::of(
                file,
                text,
                e.span().map_or(0, |s| s.start),
            )),
            message: e.message().to_string(),
        })?;
        Ok(SceneText {
            doc,
            file: file.to_string(),
            base: base.to_path_buf(),
            set: Vec::new(),
            places: Vec::new(),
        })
    }

    /// The file's name as errors give it.
    pub fn file(&self) -> &str {
        &self.file
    }

    /// The keys set so far and their values, in the order they were last
    /// set: a key set again (also spelt differently, `joints.00` for
    /// `joints.0`) replaces its earlier value, and a key whose value is
    /// replaced as a whole (`joints.0.drive` after `joints.0.drive.omega`)
    /// drops the keys inside it.
    pub fn overrides(&self) -> &[(String, SceneValue)] {
        &self.set
    }

    /// The text as it reads now.
    pub fn text(&self) -> String {
        self.doc.to_string()
    }

    /// The value at a dotted key, if the scene has one there: a table
    /// (also a `[table]` of the file) as [`SceneValue::Table`], an array of
    /// tables (`[[joints]]`) as an array of them.
    pub fn get(&self, key: &str) -> Option<SceneValue> {
        let mut node = Node::Item(self.doc.as_item());
        for s in key.split('.') {
            node = node.child(s)?;
        }
        match node {
            Node::Item(item) => item_value(item),
            Node::Table(t) => table_value(t),
            Node::Value(v) => SceneValue::from_toml(v),
        }
    }

    /// Set the value at a dotted key (see the module's documentation). The
    /// scene is not checked here; [`SceneText::spec`] and
    /// [`SceneText::load`] check it as the loader does.
    pub fn set(&mut self, key: &str, value: SceneValue) -> Result<(), SceneError> {
        let file = self.file.clone();
        let error = |message: String| SceneError {
            location: None,
            message: format!("{file}: key `{}`: {message}", shorten(key)),
        };
        let q = crate::runtime::spec::text::quoted;
        if key.len() > MAX_KEY_LEN {
            return Err(error(format!("longer than {MAX_KEY_LEN} bytes")));
        }
        let segments: Vec<&str> = key.split('.').collect();
        if segments.iter().any(|s| s.trim().is_empty()) {
            return Err(error(
                "an empty segment (keys are names and 0-based indices joined by `.`, e.g. `bodies.beam.params.e`, `joints.0.drive.omega`)".into(),
            ));
        }
        let new = value.to_toml().map_err(error)?;
        let (last, path) = segments
            .split_last()
            .expect("split gives one segment at least");
        // The place the key names (indices as numbers).
        let mut place: Vec<String> = Vec::with_capacity(segments.len());
        let mut node = NodeMut::Item(self.doc.as_item_mut());
        for (i, s) in path.iter().enumerate() {
            let here = segments[..i].join(".");
            let at = if here.is_empty() {
                "the scene".to_string()
            } else {
                format!("`{}`", q(&here))
            };
            let what = node.describe();
            let names = node.names();
            place.push(match (node.indexed(), index(s, usize::MAX)) {
                (true, Some(k)) => k.to_string(),
                _ => s.to_string(),
            });
            node = match node.child(s) {
                Some(c) => c,
                None => {
                    let s = q(s);
                    return Err(error(match names {
                        Some(n) if n.is_empty() => format!("{at} has no `{s}` (it is empty)"),
                        Some(n) => format!("{at} has no `{s}` ({what} of: {})", name_list(&n)),
                        None => format!("{at} is {what}, not a table or an array"),
                    }));
                }
            };
        }
        let here = q(&path.join("."));
        let at = if here.is_empty() {
            "the scene".to_string()
        } else {
            format!("`{here}`")
        };
        let what = node.describe();
        place.push(match (node.indexed(), index(last, usize::MAX)) {
            (true, Some(k)) => k.to_string(),
            _ => last.to_string(),
        });
        let place = place.join(".");
        // Keys this one replaces: the same place, or a place inside it.
        let replaced = |p: &String| {
            p == &place || (p.starts_with(&place) && p.as_bytes().get(place.len()) == Some(&b'.'))
        };
        let kept = self.places.iter().filter(|p| !replaced(p)).count();
        if kept >= MAX_OVERRIDES {
            return Err(error(format!(
                "more than {MAX_OVERRIDES} distinct keys set on one scene (the bound MAX_OVERRIDES; a key set again replaces its value)"
            )));
        }
        let last_q = q(last);
        let table = |t: &mut toml_edit::Table| -> Result<(), SceneError> {
            match t.get_mut(last) {
                Some(Item::Value(old)) => replace(old, new.clone()),
                Some(other) => {
                    return Err(error(format!(
                        "`{last_q}` in {at} is {}; set the values inside it",
                        describe_item(other)
                    )))
                }
                None => {
                    t.insert(last, Item::Value(new.clone()));
                }
            }
            Ok(())
        };
        match node {
            NodeMut::Item(Item::Table(t)) | NodeMut::Table(t) => table(t)?,
            NodeMut::Item(Item::Value(Value::InlineTable(t)))
            | NodeMut::Value(Value::InlineTable(t)) => match t.get_mut(last) {
                Some(old) => replace(old, new),
                None => {
                    t.insert(*last, new);
                }
            },
            NodeMut::Item(Item::Value(Value::Array(a))) | NodeMut::Value(Value::Array(a)) => {
                let len = a.len();
                match index(last, len) {
                    Some(i) => replace(a.get_mut(i).expect("index checked"), new),
                    None => {
                        return Err(error(format!(
                            "{at} is an array of {len}; `{last_q}` is not an index in it"
                        )))
                    }
                }
            }
            NodeMut::Item(Item::ArrayOfTables(_)) => {
                return Err(error(format!(
                    "{at} is an array of tables; set the values inside one of them (`{here}.0.KEY`)"
                )))
            }
            _ => return Err(error(format!("{at} is {what}, not a table or an array"))),
        }
        let mut i = 0;
        while i < self.places.len() {
            if replaced(&self.places[i]) {
                self.places.remove(i);
                self.set.remove(i);
            } else {
                i += 1;
            }
        }
        self.set.push((key.to_string(), value));
        self.places.push(place);
        Ok(())
    }

    /// Resolve the scene as the loader does (errors at `file:line:col` in
    /// the edited text, whose lines are the file's, with the keys set
    /// named).
    pub fn spec(&self) -> Result<SceneSpec, SceneError> {
        let text = self.text();
        crate::codegen::scene::resolve_str(&text, &self.file, &self.base)
            .map_err(|e| self.with_overrides(crate::scene::load::scene_error(e)))
    }

    /// Resolve and build the scene with the default kernels.
    pub fn load(&self) -> Result<Scene, SceneError> {
        self.load_with(&DefaultKernels)
    }

    /// Resolve and build the scene with another kernel provider.
    pub fn load_with(&self, provider: &dyn KernelProvider) -> Result<Scene, SceneError> {
        let spec = self.spec()?;
        crate::scene::build(&spec, provider).map_err(|e| self.with_overrides(e))
    }

    fn with_overrides(&self, mut e: SceneError) -> SceneError {
        if !self.set.is_empty() {
            let mut list: Vec<String> = self
                .set
                .iter()
                .take(MAX_LISTED)
                .map(|(k, v)| format!("{} = {}", shorten(k), shorten(&shown(v))))
                .collect();
            if self.set.len() > MAX_LISTED {
                list.push(format!("and {} more", self.set.len() - MAX_LISTED));
            }
            e.message = format!("{} (with {})", e.message, list.join(", "));
        }
        e
    }
}

/// A value as a message shows it: numbers in short form
/// ([`crate::runtime::spec::text::Num`]: `1.7e9`, not `1700000000.0`; 1e308
/// not 309 digits), the rest as TOML writes it.
fn shown(v: &SceneValue) -> String {
    match v {
        SceneValue::Float(x) => crate::runtime::spec::text::Num(*x).to_string(),
        SceneValue::Array(a) => {
            let items: Vec<String> = a.iter().take(MAX_NAMES).map(shown).collect();
            let more = if a.len() > MAX_NAMES { ", …" } else { "" };
            format!("[{}{more}]", items.join(", "))
        }
        SceneValue::Table(t) => {
            let items: Vec<String> = t
                .iter()
                .take(MAX_NAMES)
                .map(|(k, v)| format!("{k} = {}", shown(v)))
                .collect();
            let more = if t.len() > MAX_NAMES { ", …" } else { "" };
            format!("{{ {}{more} }}", items.join(", "))
        }
        other => other.to_string(),
    }
}

/// A user string as an error message carries it: escaped and cut
/// ([`crate::runtime::spec::text::snippet`]).
fn shorten(s: &str) -> String {
    crate::runtime::spec::text::snippet(s, 80)
}

/// Entry names as an error message lists them: quoted, at most
/// [`MAX_NAMES`] (then `…`).
fn name_list(names: &[String]) -> String {
    let mut out: Vec<String> = names
        .iter()
        .take(MAX_NAMES)
        .map(|n| crate::runtime::spec::text::quoted(n))
        .collect();
    if names.len() > MAX_NAMES {
        out.push(format!("… ({} in all)", names.len()));
    }
    out.join(", ")
}

/// A document item as a value: a table as [`SceneValue::Table`], an array
/// of tables as an array of them (`None`: nothing, or a date inside).
fn item_value(item: &Item) -> Option<SceneValue> {
    match item {
        Item::None => None,
        Item::Value(v) => SceneValue::from_toml(v),
        Item::Table(t) => table_value(t),
        Item::ArrayOfTables(a) => Some(SceneValue::Array(
            a.iter().map(table_value).collect::<Option<_>>()?,
        )),
    }
}

fn table_value(t: &toml_edit::Table) -> Option<SceneValue> {
    Some(SceneValue::Table(
        t.iter()
            .map(|(k, v)| Some((k.to_string(), item_value(v)?)))
            .collect::<Option<_>>()?,
    ))
}

/// Replace a value in place, keeping its surrounding whitespace and comments.
fn replace(old: &mut Value, mut new: Value) {
    *new.decor_mut() = old.decor().clone();
    *old = new;
}

fn index(segment: &str, len: usize) -> Option<usize> {
    if !segment.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    segment.parse::<usize>().ok().filter(|&i| i < len)
}

/// A place in the document, read only: items hold tables and arrays of
/// tables; inline tables and arrays hold values.
enum Node<'a> {
    Item(&'a Item),
    Table(&'a toml_edit::Table),
    Value(&'a Value),
}

impl<'a> Node<'a> {
    fn child(self, segment: &str) -> Option<Node<'a>> {
        match self {
            Node::Item(Item::Table(t)) | Node::Table(t) => t.get(segment).map(Node::Item),
            Node::Item(Item::ArrayOfTables(a)) => index(segment, a.len())
                .and_then(|i| a.get(i))
                .map(Node::Table),
            Node::Item(Item::Value(v)) | Node::Value(v) => match v {
                Value::InlineTable(t) => t.get(segment).map(Node::Value),
                Value::Array(a) => index(segment, a.len())
                    .and_then(|i| a.get(i))
                    .map(Node::Value),
                _ => None,
            },
            Node::Item(Item::None) => None,
        }
    }
}

/// A place in the document, to edit.
enum NodeMut<'a> {
    Item(&'a mut Item),
    Table(&'a mut toml_edit::Table),
    Value(&'a mut Value),
}

impl<'a> NodeMut<'a> {
    fn child(self, segment: &str) -> Option<NodeMut<'a>> {
        match self {
            NodeMut::Item(Item::Table(t)) | NodeMut::Table(t) => {
                t.get_mut(segment).map(NodeMut::Item)
            }
            NodeMut::Item(Item::ArrayOfTables(a)) => {
                let i = index(segment, a.len())?;
                a.get_mut(i).map(NodeMut::Table)
            }
            NodeMut::Item(Item::Value(v)) | NodeMut::Value(v) => match v {
                Value::InlineTable(t) => t.get_mut(segment).map(NodeMut::Value),
                Value::Array(a) => {
                    let i = index(segment, a.len())?;
                    a.get_mut(i).map(NodeMut::Value)
                }
                _ => None,
            },
            NodeMut::Item(Item::None) => None,
        }
    }

    fn names(&self) -> Option<Vec<String>> {
        let node = match self {
            NodeMut::Item(i) => Node::Item(i),
            NodeMut::Table(t) => Node::Table(t),
            NodeMut::Value(v) => Node::Value(v),
        };
        match node {
            Node::Item(Item::Table(t)) | Node::Table(t) => {
                Some(t.iter().map(|(k, _)| k.to_string()).collect())
            }
            Node::Item(Item::ArrayOfTables(a)) => {
                Some((0..a.len()).map(|i| i.to_string()).collect())
            }
            Node::Item(Item::Value(v)) | Node::Value(v) => match v {
                Value::InlineTable(t) => Some(t.iter().map(|(k, _)| k.to_string()).collect()),
                Value::Array(a) => Some((0..a.len()).map(|i| i.to_string()).collect()),
                _ => None,
            },
            Node::Item(Item::None) => None,
        }
    }

    /// Whether the entries are indexed (an array, an array of tables).
    fn indexed(&self) -> bool {
        matches!(
            self,
            NodeMut::Item(Item::ArrayOfTables(_) | Item::Value(Value::Array(_)))
                | NodeMut::Value(Value::Array(_))
        )
    }

    fn describe(&self) -> &'static str {
        match self {
            NodeMut::Item(i) => describe_item(i),
            NodeMut::Table(_) => "a table",
            NodeMut::Value(v) => describe_value(v),
        }
    }
}

fn describe_item(item: &Item) -> &'static str {
    match item {
        Item::None => "nothing",
        Item::Table(_) => "a table",
        Item::ArrayOfTables(_) => "an array of tables",
        Item::Value(v) => describe_value(v),
    }
}

fn describe_value(v: &Value) -> &'static str {
    match v {
        Value::String(_) => "a string",
        Value::Integer(_) => "an integer",
        Value::Float(_) => "a number",
        Value::Boolean(_) => "a boolean",
        Value::Datetime(_) => "a date",
        Value::Array(_) => "an array",
        Value::InlineTable(_) => "an inline table",
    }
}
