//! ParaView time series and mode-shape animations (feature `vtk`): VTK XML
//! PolyData files (`.vtp`, written by the `vtkio` crate) and a ParaView
//! collection (`.pvd`) listing them with their times.
//!
//! What a file holds (global frame, the scene's units):
//!
//! - every flexible beam body's deformed axis as one polyline through its
//!   nodes and [`POINTS_BETWEEN_NODES`] points between each pair, each
//!   point placed by the body's point shape ([`crate::runtime::Body::point_shape`],
//!   the same evaluation as the scene's position outputs);
//! - every finite-element body's nodes as vertices, each placed by the
//!   body's node shape ([`crate::runtime::Body::node_shape`], the same
//!   evaluation as the scene's outputs at `NAME@node=N`);
//! - every rigid body as one vertex at its frame's origin, and every joint
//!   (constraint) as one vertex at its marker `a`.
//!
//! Point data (one value per point): `displacement` (the elastic
//! displacement `A Σ s_j q_j`, global axes), `rotation` (the section's small
//! rotation `A ψ`, global axes; 0 at an FE node, which has no rotation),
//! `axis_x`, `axis_y`, `axis_z` (the section's axes `A R_s(ψ) e_k`, exact
//! (docs/theory.md §16); in a mode shape's animation `A (e_k + ψ × e_k)`; a
//! rigid body's, an FE body's or a joint marker's axes), `x` (the point's
//! place on the undeformed axis; 0 for vertices), `body` (the body's index
//! in the scene, -1 for a joint) and `kind` (0 a point between nodes, 1 a
//! node, 2 a rigid body's frame, 3 a joint). A file that draws an FE body
//! has one more array, `node`: an FE node's number, -1 for every other
//! point (a file without FE bodies has none, so beams' files are as they
//! were).
//!
//! The points of a body come from a [`DrawnBody`]: a beam's axis
//! ([`Drawn::Axis`], one polyline), an FE body's nodes ([`Drawn::Nodes`],
//! vertices, no polyline), a rigid body's frame or a joint.
//!
//! Files: `DIR/<name>.pvd` and `DIR/<name>_<step>.vtp`. Each is written to
//! a temporary file in `DIR` and renamed over its target. An existing file
//! is replaced only if it is a regular file that ffr wrote (it starts with
//! [`MARK`]); anything else (a directory, a symbolic link, a device, a file
//! without the mark) is refused before anything is written.

use super::model::Scene;
use crate::runtime::marker::{BodyId, Marker, MarkerKin};
use crate::runtime::nalgebra::{Complex, Vector3};
use crate::runtime::{Body, PointShape, System};
use std::io::Write;
use std::path::{Path, PathBuf};
use vtkio::model::{
    Attribute, Attributes, ByteOrder, DataArray, DataSet, ElementType, PolyDataPiece, Version,
    VertexNumbers, Vtk,
};

/// The most step files one series writes (a run with more samples needs
/// `every` ≥ samples / this bound).
pub const MAX_VTK_FILES: usize = 10_000;

/// Points drawn between two neighbouring nodes of a beam's axis (at equal
/// spacing in the undeformed `x`).
pub const POINTS_BETWEEN_NODES: usize = 3;

/// How every file ffr writes here starts: an existing file is replaced only
/// if it starts with this.
pub const MARK: &str =
    "<?xml version=\"1.0\"?>\n<!-- written by ffr (ParaView time series); ffr may replace it -->\n";

/// A time series to write during a run: into `dir`, one step file per
/// `every` recorded samples (the first sample, the initial state, always).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VtkOptions {
    /// The directory (created if needed).
    pub dir: PathBuf,
    /// Write samples `0, every, 2·every, …` (≥ 1).
    pub every: usize,
}

impl VtkOptions {
    /// Every sample into `dir`.
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        Self {
            dir: dir.into(),
            every: 1,
        }
    }
}

/// How a body is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Drawn {
    /// A beam's axis: one polyline through its points in order.
    Axis,
    /// A body of nodes (finite elements): its points, the nodes `0, 1, …`
    /// in order, as vertices.
    Nodes,
    /// A rigid body: its frame's origin as one vertex.
    Frame,
    /// A joint: its marker `a` as one vertex.
    Joint,
}

/// A point of a body to draw.
#[derive(Clone, Debug)]
pub struct DrawnPoint {
    /// Where (a marker of the body, moved by its elastic coordinates).
    pub marker: Marker,
    /// The same point, not moved by elastic coordinates, with the body's
    /// axes: gives the frame's rotation `A` (its axes' columns).
    pub frame: Marker,
    /// Undeformed `x` on the axis (0 off an axis).
    pub x: f64,
    /// Whether it is a node.
    pub node: bool,
}

/// A body (or joint) and its points to draw.
#[derive(Clone, Debug)]
pub struct DrawnBody {
    /// Its name (for messages).
    pub name: String,
    /// Its index in the scene (`None` for a joint).
    pub body: Option<BodyId>,
    /// How.
    pub kind: Drawn,
    /// The points.
    pub points: Vec<DrawnPoint>,
}

/// The nodes' `x` of a flexible body: the graded mesh's, or
/// [`equal_nodes`].
pub fn node_xs(f: &super::FlexSpec) -> Vec<f64> {
    match &f.nodes {
        Some(x) => x.clone(),
        None => equal_nodes(f.elements, f.params.length),
    }
}

/// The `elements + 1` nodes' `x` of equal elements over `length` (the last
/// exactly `length`).
pub fn equal_nodes(elements: usize, length: f64) -> Vec<f64> {
    let n = elements.max(1);
    (0..=n)
        .map(|i| {
            if i == n {
                length
            } else {
                length * i as f64 / n as f64
            }
        })
        .collect()
}

/// The points drawn on an axis with these nodes: `(x, is a node)`, each
/// node followed by [`POINTS_BETWEEN_NODES`] points at equal steps to the
/// next.
pub fn axis_points(nodes: &[f64]) -> Vec<(f64, bool)> {
    let m = POINTS_BETWEEN_NODES + 1;
    let mut xs = Vec::with_capacity(nodes.len() * m);
    for (j, &x) in nodes.iter().enumerate() {
        xs.push((x, true));
        if let Some(&next) = nodes.get(j + 1) {
            xs.extend((1..m).map(|k| (x + (next - x) * k as f64 / m as f64, false)));
        }
    }
    xs
}

/// What a scene draws: its flexible bodies' axes and FE bodies' nodes (in
/// body order), its rigid bodies' frames, its joints.
pub fn drawing(scene: &Scene) -> crate::Result<Vec<DrawnBody>> {
    let sys = &scene.system;
    let mut out = Vec::new();
    for (i, e) in sys.bodies().iter().enumerate() {
        let id = BodyId(i);
        let rigid = |u0: Vector3<f64>| Marker::at(id, u0);
        let nodes = e.body.node_count();
        if nodes > 0 {
            let mut points = Vec::with_capacity(nodes);
            for n in 0..nodes {
                let marker = sys.node(id, n)?;
                let frame = rigid(Vector3::from(marker.shape.u0));
                points.push(DrawnPoint {
                    marker,
                    frame,
                    x: 0.0,
                    node: true,
                });
            }
            out.push(DrawnBody {
                name: e.name.clone(),
                body: Some(id),
                kind: Drawn::Nodes,
                points,
            });
        } else if sys.is_outboard_segment(id) {
            // Drawn with its body's root segment, as one line.
            continue;
        } else if let Some(f) = scene.flex.iter().find(|f| f.name == e.name) {
            let mut points = Vec::new();
            for (x, node) in axis_points(&node_xs(f)) {
                // On a segmented body, the point's own segment (and frame).
                let marker = sys.point(id, x)?;
                let frame = Marker::at(marker.body.unwrap_or(id), Vector3::from(marker.shape.u0));
                points.push(DrawnPoint {
                    marker,
                    frame,
                    x,
                    node,
                });
            }
            out.push(DrawnBody {
                name: e.name.clone(),
                body: Some(id),
                kind: Drawn::Axis,
                points,
            });
        } else {
            out.push(DrawnBody {
                name: e.name.clone(),
                body: Some(id),
                kind: Drawn::Frame,
                points: vec![DrawnPoint {
                    marker: Marker::origin(id),
                    frame: Marker::origin(id),
                    x: 0.0,
                    node: false,
                }],
            });
        }
    }
    for c in sys.constraints() {
        let frame = match c.a.body {
            Some(b) => Marker::at(b, Vector3::from(c.a.shape.u0)),
            None => c.a.clone(),
        };
        out.push(DrawnBody {
            name: c.kind.clone(),
            body: None,
            kind: Drawn::Joint,
            points: vec![DrawnPoint {
                marker: c.a.clone(),
                frame,
                x: 0.0,
                node: false,
            }],
        });
    }
    Ok(out)
}

/// A drawing evaluated at configurations: markers' workspaces allocated once.
pub struct Frames {
    bodies: Vec<DrawnBody>,
    kins: Vec<Vec<(MarkerKin, MarkerKin)>>,
}

impl Frames {
    /// Workspaces for `bodies` of `sys`.
    pub fn new(sys: &System<Box<dyn Body>>, bodies: Vec<DrawnBody>) -> Self {
        let kins = bodies
            .iter()
            .map(|b| {
                b.points
                    .iter()
                    .map(|p| (sys.marker_kin(&p.marker), sys.marker_kin(&p.frame)))
                    .collect()
            })
            .collect();
        Self { bodies, kins }
    }

    /// The bodies drawn.
    pub fn bodies(&self) -> &[DrawnBody] {
        &self.bodies
    }

    /// The largest elastic displacement at a node of the complex motion `v`
    /// (one value per system coordinate): `max √(|u(Re v)|² + |u(Im v)|²)`
    /// over the drawn nodes, `u` the node's elastic displacement (body axes).
    pub fn elastic_amplitude(&self, v: &[Complex<f64>]) -> f64 {
        let mut m = 0.0f64;
        for (b, kins) in self.bodies.iter().zip(&self.kins) {
            for (p, (k, _)) in b.points.iter().zip(kins).filter(|(p, _)| p.node) {
                let (mut re, mut im) = (Vector3::zeros(), Vector3::zeros());
                for (j, (_, s, _)) in p.marker.shape.entries.iter().enumerate() {
                    let vj = v[k.idx[k.n_frame + j]];
                    re += Vector3::from(*s) * vj.re;
                    im += Vector3::from(*s) * vj.im;
                }
                m = m.max((re.norm_squared() + im.norm_squared()).sqrt());
            }
        }
        m
    }

    /// The drawing at the coordinates `q`, as one PolyData piece.
    pub fn piece(&mut self, q: &[f64]) -> PolyDataPiece {
        let mut out = Piece {
            fe_nodes: self.bodies.iter().any(|b| b.kind == Drawn::Nodes),
            ..Piece::default()
        };
        for (b, kins) in self.bodies.iter().zip(&mut self.kins) {
            let first = out.len();
            for (n, (p, (k, k0))) in b.points.iter().zip(kins.iter_mut()).enumerate() {
                k.eval(&p.marker, q);
                k0.eval(&p.frame, q);
                // The frame's axes (columns of A) at the point.
                let a = k0.axes;
                let (mut d, mut psi) = (Vector3::zeros(), Vector3::zeros());
                for (j, (_, s, r)) in p.marker.shape.entries.iter().enumerate() {
                    let qj = q[k.idx[k.n_frame + j]];
                    d += Vector3::from(*s) * qj;
                    psi += Vector3::from(*r) * qj;
                }
                let global = |v: Vector3<f64>| a[0] * v.x + a[1] * v.y + a[2] * v.z;
                out.push(PointValues {
                    pos: k.pos,
                    displacement: global(d),
                    rotation: global(psi),
                    axes: k.axes,
                    x: p.x,
                    body: b.body.map_or(-1, |id| id.0 as i32),
                    kind: kind_code(b.kind, p.node),
                    node: fe_node(b.kind, n),
                });
            }
            out.cell(b.kind, first);
        }
        out.finish()
    }
}

/// The `kind` point value: 0 a point between nodes, 1 a node, 2 a rigid
/// body's frame, 3 a joint.
fn kind_code(kind: Drawn, node: bool) -> i32 {
    match kind {
        Drawn::Axis | Drawn::Nodes => i32::from(node),
        Drawn::Frame => 2,
        Drawn::Joint => 3,
    }
}

/// The `node` point value: an FE body's `n`-th point is its node `n`; -1
/// for every other point.
fn fe_node(kind: Drawn, n: usize) -> i32 {
    match kind {
        Drawn::Nodes => i32::try_from(n).unwrap_or(i32::MAX),
        Drawn::Axis | Drawn::Frame | Drawn::Joint => -1,
    }
}

/// One point's values (global axes).
struct PointValues {
    pos: Vector3<f64>,
    displacement: Vector3<f64>,
    rotation: Vector3<f64>,
    axes: [Vector3<f64>; 3],
    x: f64,
    body: i32,
    kind: i32,
    node: i32,
}

/// A PolyData piece being assembled: point values, then each body's cell.
/// With `fe_nodes` (the piece draws an FE body) it has the point array
/// `node`.
#[derive(Default)]
struct Piece {
    fe_nodes: bool,
    points: Vec<f64>,
    disp: Vec<f64>,
    rot: Vec<f64>,
    axes: [Vec<f64>; 3],
    xs: Vec<f64>,
    body: Vec<i32>,
    kind: Vec<i32>,
    node: Vec<i32>,
    lines: (Vec<u64>, Vec<u64>),
    verts: (Vec<u64>, Vec<u64>),
}

impl Piece {
    fn len(&self) -> u64 {
        self.xs.len() as u64
    }

    fn push(&mut self, p: PointValues) {
        self.points.extend(p.pos.iter());
        self.disp.extend(p.displacement.iter());
        self.rot.extend(p.rotation.iter());
        for c in 0..3 {
            self.axes[c].extend(p.axes[c].iter());
        }
        self.xs.push(p.x);
        self.body.push(p.body);
        self.kind.push(p.kind);
        self.node.push(p.node);
    }

    /// The points from `first` on as one body drawn as `kind`.
    fn cell(&mut self, kind: Drawn, first: u64) {
        let last = self.len();
        match kind {
            Drawn::Axis => {
                self.lines.0.extend(first..last);
                self.lines.1.push(self.lines.0.len() as u64);
            }
            Drawn::Nodes | Drawn::Frame | Drawn::Joint => {
                for i in first..last {
                    self.verts.0.push(i);
                    self.verts.1.push(self.verts.0.len() as u64);
                }
            }
        }
    }

    fn finish(self) -> PolyDataPiece {
        let vectors = |name: &str, v: Vec<f64>| {
            Attribute::DataArray(DataArray {
                name: name.into(),
                elem: ElementType::Vectors,
                data: v.into(),
            })
        };
        let scalars = |name: &str, data: vtkio::IOBuffer| {
            Attribute::DataArray(DataArray {
                name: name.into(),
                elem: ElementType::Scalars {
                    num_comp: 1,
                    lookup_table: None,
                },
                data,
            })
        };
        let [ax, ay, az] = self.axes;
        let cells = |(conn, off): (Vec<u64>, Vec<u64>)| {
            (!off.is_empty()).then_some(VertexNumbers::XML {
                connectivity: conn,
                offsets: off,
            })
        };
        let mut point = vec![
            vectors("displacement", self.disp),
            vectors("rotation", self.rot),
            vectors("axis_x", ax),
            vectors("axis_y", ay),
            vectors("axis_z", az),
            scalars("x", self.xs.into()),
            scalars("body", self.body.into()),
            scalars("kind", self.kind.into()),
        ];
        if self.fe_nodes {
            point.push(scalars("node", self.node.into()));
        }
        PolyDataPiece {
            points: self.points.into(),
            verts: cells(self.verts),
            lines: cells(self.lines),
            polys: None,
            strips: None,
            data: Attributes {
                point,
                cell: Vec::new(),
            },
        }
    }
}

/// A PolyData file's text: [`MARK`], then the VTK XML (binary data inline,
/// base64, little endian).
pub fn vtp_text(piece: PolyDataPiece) -> crate::Result<Vec<u8>> {
    let vtk = Vtk {
        version: Version::new_xml(1, 0),
        title: String::new(),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::inline(piece),
    };
    let mut out = MARK.as_bytes().to_vec();
    vtk.write_xml(&mut out)
        .map_err(|e| crate::Error::Invalid(format!("cannot write the VTK file: {e}")))?;
    out.push(b'\n');
    Ok(out)
}

/// A ParaView collection's text: [`MARK`], then `<VTKFile
/// type="Collection">` with one `<DataSet timestep=… file=…/>` per
/// `(time, file name)` (times in the shortest form that reads back to the
/// same `f64`).
pub fn pvd_text(steps: &[(f64, String)]) -> crate::Result<Vec<u8>> {
    use quick_xml::events::{BytesEnd, BytesStart, Event};
    let mut w = quick_xml::Writer::new_with_indent(Vec::new(), b' ', 2);
    let e = |e: quick_xml::Error| crate::Error::Invalid(format!("cannot write the .pvd: {e}"));
    let mut root = BytesStart::new("VTKFile");
    root.push_attribute(("type", "Collection"));
    root.push_attribute(("version", "0.1"));
    root.push_attribute(("byte_order", "LittleEndian"));
    w.write_event(Event::Start(root)).map_err(e)?;
    w.write_event(Event::Start(BytesStart::new("Collection")))
        .map_err(e)?;
    for (t, file) in steps {
        let mut d = BytesStart::new("DataSet");
        let t = format!("{t:?}");
        d.push_attribute(("timestep", t.as_str()));
        d.push_attribute(("group", ""));
        d.push_attribute(("part", "0"));
        d.push_attribute(("file", file.as_str()));
        w.write_event(Event::Empty(d)).map_err(e)?;
    }
    w.write_event(Event::End(BytesEnd::new("Collection")))
        .map_err(e)?;
    w.write_event(Event::End(BytesEnd::new("VTKFile")))
        .map_err(e)?;
    let mut out = MARK.as_bytes().to_vec();
    out.extend(w.into_inner());
    out.push(b'\n');
    Ok(out)
}

/// `Ok` if `path` may be written: it does not exist, or it is a regular
/// file that starts with [`MARK`]. Otherwise an error naming the path and
/// what it is.
pub fn check_ours(path: &Path) -> crate::Result<()> {
    let meta = match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => {
            return Err(crate::Error::Invalid(format!(
                "{}: cannot be examined: {e}",
                path.display()
            )))
        }
        Ok(m) => m,
    };
    let t = meta.file_type();
    if !t.is_file() {
        let what = if t.is_dir() {
            "a directory"
        } else if t.is_symlink() {
            "a symbolic link"
        } else {
            "not a regular file"
        };
        return Err(crate::Error::Invalid(format!(
            "{}: is {what}, not a regular file: not replaced (remove it or write the series to another directory)",
            path.display()
        )));
    }
    let mut head = Vec::new();
    {
        use std::io::Read;
        let f = std::fs::File::open(path)
            .map_err(|e| crate::Error::Invalid(format!("{}: {e}", path.display())))?;
        f.take(MARK.len() as u64)
            .read_to_end(&mut head)
            .map_err(|e| crate::Error::Invalid(format!("{}: {e}", path.display())))?;
    }
    if head == MARK.as_bytes() {
        Ok(())
    } else {
        Err(crate::Error::Invalid(format!(
            "{}: exists and was not written by ffr: not replaced (remove it or write the series to another directory)",
            path.display()
        )))
    }
}

/// Check `dir` (a directory, or nothing yet) and create it.
pub fn prepare_dir(dir: &Path) -> crate::Result<()> {
    if let Ok(m) = std::fs::metadata(dir) {
        if !m.is_dir() {
            return Err(crate::Error::Invalid(format!(
                "{}: exists and is not a directory (the VTK series is written into a directory)",
                dir.display()
            )));
        }
    }
    std::fs::create_dir_all(dir).map_err(|e| {
        crate::Error::Invalid(format!(
            "{}: cannot create the directory: {e}",
            dir.display()
        ))
    })
}

/// Write `contents` to `path` atomically: a synced temporary file in the
/// same directory, renamed over `path` after [`check_ours`] once more.
pub fn write_atomic(path: &Path, contents: &[u8]) -> crate::Result<()> {
    let fail =
        |e: std::io::Error| crate::Error::Invalid(format!("{}: cannot write: {e}", path.display()));
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut tmp = tempfile::Builder::new()
        .prefix(&format!(".{name}."))
        .suffix(".tmp")
        .tempfile_in(dir)
        .map_err(fail)?;
    tmp.write_all(contents).map_err(fail)?;
    tmp.as_file().sync_all().map_err(fail)?;
    check_ours(path)?;
    tmp.persist(path).map_err(|e| fail(e.error))?;
    Ok(())
}

/// A file name's stem for a series: `name` with path separators and control
/// characters replaced by `_` (`scene` if empty).
pub fn series_name(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c == '/' || c == '\\' || c.is_control() {
                '_'
            } else {
                c
            }
        })
        .collect();
    if s.is_empty() || s == "." || s == ".." {
        "scene".into()
    } else {
        s
    }
}

/// The name of a series' scene file without directory or extension.
pub fn scene_stem(origin: &str) -> String {
    series_name(
        &Path::new(origin)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
    )
}

/// Files a series wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct VtkWritten {
    /// The `.pvd`.
    pub pvd: PathBuf,
    /// Each step file's time and path, in order.
    pub steps: Vec<(f64, PathBuf)>,
}

/// A time series written while a scene runs ([`super::run_with`]).
pub struct VtkSeries {
    dir: PathBuf,
    name: String,
    every: usize,
    width: usize,
    frames: Frames,
    sample: usize,
    written: Vec<(f64, String)>,
}

impl VtkSeries {
    /// A series of `scene` named `name` (`DIR/<name>.pvd`), checked before
    /// the run: `every` ≥ 1, at most [`MAX_VTK_FILES`] step files for the
    /// scene's samples (`t_end / dt` steps and the initial state), the
    /// directory usable and no file it would write refused by
    /// [`check_ours`].
    pub fn new(scene: &Scene, options: &VtkOptions, name: &str) -> crate::Result<Self> {
        if options.every == 0 {
            return Err(crate::Error::Invalid(
                "every = 0: the VTK series writes every K-th sample, K ≥ 1".into(),
            ));
        }
        let steps = (scene.t_end / scene.dt - 1e-9).ceil().max(0.0);
        let samples = steps + 1.0;
        let files = (samples / options.every as f64).ceil();
        if !(files <= MAX_VTK_FILES as f64) {
            let need = (samples / MAX_VTK_FILES as f64).ceil();
            return Err(crate::Error::Invalid(format!(
                "{}: {samples} samples with every = {} would write {files} VTK files, more than the limit of {MAX_VTK_FILES}: use every ≥ {need} (--every {need})",
                scene.origin, options.every
            )));
        }
        let last = (steps as usize / options.every) * options.every;
        let width = last.to_string().len().max(4);
        let name = series_name(name);
        let dir = options.dir.clone();
        prepare_dir(&dir)?;
        check_ours(&dir.join(format!("{name}.pvd")))?;
        for i in (0..=last).step_by(options.every) {
            check_ours(&dir.join(format!("{name}_{i:0width$}.vtp")))?;
        }
        let frames = Frames::new(&scene.system, drawing(scene)?);
        Ok(Self {
            dir,
            name,
            every: options.every,
            width,
            frames,
            sample: 0,
            written: Vec::new(),
        })
    }

    /// The next recorded sample at time `t`, coordinates `q`: written if it
    /// is one of every `every`.
    pub fn observe(&mut self, t: f64, q: &[f64]) -> crate::Result<()> {
        let i = self.sample;
        self.sample += 1;
        if !i.is_multiple_of(self.every) {
            return Ok(());
        }
        if let Some(j) = q.iter().position(|x| !x.is_finite()) {
            return Err(crate::Error::Invalid(format!(
                "coordinate {j} is {} at t = {t} s, not a finite number: the VTK series stops before it ({} files written)",
                q[j],
                self.written.len()
            )));
        }
        if self.written.len() >= MAX_VTK_FILES {
            return Err(crate::Error::Invalid(format!(
                "more than {MAX_VTK_FILES} VTK files: not written"
            )));
        }
        let width = self.width;
        let file = format!("{}_{i:0width$}.vtp", self.name);
        let text = vtp_text(self.frames.piece(q))?;
        write_atomic(&self.dir.join(&file), &text)?;
        self.written.push((t, file));
        Ok(())
    }

    /// Write the `.pvd` listing the step files written.
    pub fn finish(self) -> crate::Result<VtkWritten> {
        let pvd = self.dir.join(format!("{}.pvd", self.name));
        write_atomic(&pvd, &pvd_text(&self.written)?)?;
        Ok(VtkWritten {
            pvd,
            steps: self
                .written
                .into_iter()
                .map(|(t, f)| (t, self.dir.join(f)))
                .collect(),
        })
    }
}

/// Frames of a mode-shape animation: one period at equal phase steps
/// (the frame after the last is the first again).
pub const FRAMES_PER_PERIOD: usize = 24;

/// A mode shape's amplitude in its animation: the largest node
/// displacement is this fraction of the body's length (an FE body's: its
/// [`nodes_size`]; a mode that moves no node, only rotates sections: the
/// largest section rotation is this many radians).
pub const MODE_AMPLITUDE: f64 = 0.1;

/// One mode to animate: its label, its angular frequency (rad/s; `None`
/// for a static constraint mode: the times are then fractions of one
/// period) and its shape (one value per elastic coordinate).
#[derive(Clone, Debug, PartialEq)]
pub struct ModeShape {
    /// The label (`ffr modes --json`'s `labels`).
    pub label: String,
    /// `ω` (rad/s).
    pub omega: Option<f64>,
    /// `φ` (n_f values, the body's elastic coordinates).
    pub phi: Vec<f64>,
}

/// The scale `a` of a mode in its animation (frame `k` shows
/// `q_f = a cos(2π k / FRAMES_PER_PERIOD) φ`): [`MODE_AMPLITUDE`] × `length`
/// over the largest node displacement of `φ` (body axes), or
/// [`MODE_AMPLITUDE`] over the largest section rotation if no node moves.
pub fn mode_scale(body: &dyn Body, nodes: &[f64], length: f64, phi: &[f64]) -> crate::Result<f64> {
    let (mut umax, mut rmax) = (0.0f64, 0.0f64);
    for &x in nodes {
        let (u, r) = shape_at(body, x, phi)?;
        umax = umax.max(u.norm());
        rmax = rmax.max(r.norm());
    }
    if umax > 0.0 {
        Ok(MODE_AMPLITUDE * length / umax)
    } else if rmax > 0.0 {
        Ok(MODE_AMPLITUDE / rmax)
    } else {
        Err(crate::Error::Invalid(
            "a mode that moves no node: nothing to animate".into(),
        ))
    }
}

/// `(Σ s_j φ_j, Σ ψ_j φ_j)` at `x` (body axes).
fn shape_at(body: &dyn Body, x: f64, phi: &[f64]) -> crate::Result<(Vector3<f64>, Vector3<f64>)> {
    shape_values(&body.point_shape(x)?, phi)
}

/// `(Σ s_j φ_j, Σ ψ_j φ_j)` of the point shape `s` (body axes).
fn shape_values(s: &PointShape, phi: &[f64]) -> crate::Result<(Vector3<f64>, Vector3<f64>)> {
    let (mut u, mut r) = (Vector3::zeros(), Vector3::zeros());
    for (dof, sj, pj) in &s.entries {
        let v = phi.get(*dof).copied().ok_or_else(|| {
            crate::Error::Invalid(format!(
                "the mode has {} values, the body's coordinate {dof} has none",
                phi.len()
            ))
        })?;
        u += Vector3::from(*sj) * v;
        r += Vector3::from(*pj) * v;
    }
    Ok((u, r))
}

/// The file names of `count` mode animations named `name`: the `.pvd` stem
/// of mode `j` (0-based; `<name>_mode<j+1>`, at least two digits) and the
/// name of its frame `k` (`<stem>_<k>.vtp`, two digits).
#[allow(clippy::type_complexity)]
pub fn mode_names(
    name: &str,
    count: usize,
) -> (
    impl Fn(usize) -> String + '_,
    impl Fn(usize, usize) -> String + '_,
) {
    let jw = count.to_string().len().max(2);
    let kw = (FRAMES_PER_PERIOD - 1).to_string().len();
    let stem = move |j: usize| format!("{name}_mode{:0jw$}", j + 1);
    let frame = move |j: usize, k: usize| format!("{name}_mode{:0jw$}_{k:0kw$}.vtp", j + 1);
    (stem, frame)
}

/// Check `dir` and every file of `count` mode animations named `name`
/// ([`check_ours`]), and create `dir`; at most [`MAX_VTK_FILES`] files.
pub fn check_mode_files(dir: &Path, name: &str, count: usize) -> crate::Result<()> {
    let files = count.saturating_mul(FRAMES_PER_PERIOD + 1);
    if files > MAX_VTK_FILES {
        return Err(crate::Error::Invalid(format!(
            "{count} mode animations of {} files each: {files} VTK files, more than the limit of {MAX_VTK_FILES}",
            FRAMES_PER_PERIOD + 1
        )));
    }
    let (stem, frame) = mode_names(name, count);
    prepare_dir(dir)?;
    for j in 0..count {
        check_ours(&dir.join(format!("{}.pvd", stem(j))))?;
        for k in 0..FRAMES_PER_PERIOD {
            check_ours(&dir.join(frame(j, k)))?;
        }
    }
    Ok(())
}

/// Write one animation per mode of a beam body (drawn in its own frame:
/// origin at 0, body axes as global axes): `DIR/<name>_mode<j>.pvd` and
/// `DIR/<name>_mode<j>_<k>.vtp`, `j` from 1, `k` from 0 to
/// [`FRAMES_PER_PERIOD`] − 1 at times `k T / FRAMES_PER_PERIOD`, `T = 2π/ω`.
/// The axis is drawn as in a run (nodes at `nodes`,
/// [`POINTS_BETWEEN_NODES`] points between), scaled by [`mode_scale`]. Every
/// file is checked ([`check_ours`]) before any is written.
pub fn write_modes(
    dir: &Path,
    name: &str,
    body: &dyn Body,
    nodes: &[f64],
    length: f64,
    modes: &[ModeShape],
) -> crate::Result<Vec<VtkWritten>> {
    let name = series_name(name);
    check_mode_files(dir, &name, modes.len())?;
    let xs = axis_points(nodes);
    let scales = modes
        .iter()
        .map(|m| mode_scale(body, nodes, length, &m.phi))
        .collect::<crate::Result<Vec<f64>>>()?;
    animate_modes(dir, &name, modes, &scales, |mode, a| {
        let mut piece = Piece::default();
        for &(x, node) in &xs {
            let u0 = Vector3::from(body.point_shape(x)?.u0);
            let (u, r) = shape_at(body, x, &mode.phi)?;
            piece.push(mode_point(u0, u * a, r * a, x, node, -1));
        }
        piece.cell(Drawn::Axis, 0);
        Ok(piece)
    })
}

/// The size of a body of nodes (an FE body): the longest side of its nodes'
/// bounding box in body axes (1 if the nodes coincide, or it has none).
pub fn nodes_size(body: &dyn Body) -> crate::Result<f64> {
    let (mut lo, mut hi) = (
        Vector3::repeat(f64::INFINITY),
        Vector3::repeat(f64::NEG_INFINITY),
    );
    for n in 0..body.node_count() {
        let u0 = Vector3::from(body.node_shape(n)?.u0);
        lo = lo.inf(&u0);
        hi = hi.sup(&u0);
    }
    let size = (hi - lo).max();
    Ok(if size > 0.0 && size.is_finite() {
        size
    } else {
        1.0
    })
}

/// Write one animation per mode of an FE body (a body of nodes,
/// [`Body::node_count`] > 0), as [`write_modes`] does for a beam: the body in
/// its own frame, its nodes as vertices placed by their node shapes
/// (`x̄_N + a cos(2π k / FRAMES_PER_PERIOD) Φ_N φ`), point data as in a run
/// (with `node`). The scale `a` makes the largest node displacement
/// [`MODE_AMPLITUDE`] × [`nodes_size`]. Every file is checked
/// ([`check_ours`]) before any is written.
pub fn write_node_modes(
    dir: &Path,
    name: &str,
    body: &dyn Body,
    modes: &[ModeShape],
) -> crate::Result<Vec<VtkWritten>> {
    let name = series_name(name);
    check_mode_files(dir, &name, modes.len())?;
    let shapes = (0..body.node_count())
        .map(|n| body.node_shape(n))
        .collect::<std::result::Result<Vec<_>, _>>()?;
    if shapes.is_empty() {
        return Err(crate::Error::Invalid(
            "the body has no nodes to draw its modes at".into(),
        ));
    }
    let size = nodes_size(body)?;
    let scales = modes
        .iter()
        .map(|m| {
            let mut umax = 0.0f64;
            for s in &shapes {
                umax = umax.max(shape_values(s, &m.phi)?.0.norm());
            }
            if umax > 0.0 {
                Ok(MODE_AMPLITUDE * size / umax)
            } else {
                Err(crate::Error::Invalid(
                    "a mode that moves no node: nothing to animate".into(),
                ))
            }
        })
        .collect::<crate::Result<Vec<f64>>>()?;
    animate_modes(dir, &name, modes, &scales, |mode, a| {
        let mut piece = Piece {
            fe_nodes: true,
            ..Piece::default()
        };
        for (n, s) in shapes.iter().enumerate() {
            let (u, r) = shape_values(s, &mode.phi)?;
            let node = fe_node(Drawn::Nodes, n);
            piece.push(mode_point(
                Vector3::from(s.u0),
                u * a,
                r * a,
                0.0,
                true,
                node,
            ));
        }
        piece.cell(Drawn::Nodes, 0);
        Ok(piece)
    })
}

/// A point of a mode's frame (body 0): at `u0 + u`, section axes turned by
/// `r`.
fn mode_point(
    u0: Vector3<f64>,
    u: Vector3<f64>,
    r: Vector3<f64>,
    x: f64,
    node: bool,
    fe_node: i32,
) -> PointValues {
    let e = [Vector3::x(), Vector3::y(), Vector3::z()];
    PointValues {
        pos: u0 + u,
        displacement: u,
        rotation: r,
        axes: e.map(|c| c + r.cross(&c)),
        x,
        body: 0,
        kind: i32::from(node),
        node: fe_node,
    }
}

/// Write the animations of `modes` named `name` (files checked already):
/// frame `k` of mode `j` is `piece(mode, scales[j] cos(2π k /
/// FRAMES_PER_PERIOD))` at time `k T / FRAMES_PER_PERIOD`, `T = 2π/ω` (1
/// without `ω`).
fn animate_modes(
    dir: &Path,
    name: &str,
    modes: &[ModeShape],
    scales: &[f64],
    mut piece: impl FnMut(&ModeShape, f64) -> crate::Result<Piece>,
) -> crate::Result<Vec<VtkWritten>> {
    let (stem, frame_file) = mode_names(name, modes.len());
    let mut written = Vec::with_capacity(modes.len());
    for ((j, mode), &scale) in modes.iter().enumerate().zip(scales) {
        let period = mode
            .omega
            .filter(|w| *w > 0.0 && w.is_finite())
            .map_or(1.0, |w| std::f64::consts::TAU / w);
        let mut steps = Vec::with_capacity(FRAMES_PER_PERIOD);
        for k in 0..FRAMES_PER_PERIOD {
            let phase = std::f64::consts::TAU * k as f64 / FRAMES_PER_PERIOD as f64;
            let a = scale * phase.cos();
            let file = frame_file(j, k);
            let text = vtp_text(piece(mode, a)?.finish())?;
            write_atomic(&dir.join(&file), &text)?;
            steps.push((period * k as f64 / FRAMES_PER_PERIOD as f64, file));
        }
        let pvd = dir.join(format!("{}.pvd", stem(j)));
        write_atomic(&pvd, &pvd_text(&steps)?)?;
        written.push(VtkWritten {
            pvd,
            steps: steps.into_iter().map(|(t, f)| (t, dir.join(f))).collect(),
        });
    }
    Ok(written)
}

/// A mode's vector in a system's coordinates: `(index, value)` pairs
/// ([`super::linear::CampbellMode::vector`]).
pub type ModeVector = [(usize, Complex<f64>)];

/// Write one animation per mode of a linearized scene (a Campbell
/// diagram's speed): the scene drawn as in a run at `q0 + a Re(e^{iφ} v)`,
/// `φ = 2π k / FRAMES_PER_PERIOD`, `v` the mode's vector, at times
/// `k T / FRAMES_PER_PERIOD`, `T = 2π/ω` (1 if `ω` = 0): files
/// `DIR/<name>_mode<j>.pvd` and `DIR/<name>_mode<j>_<k>.vtp`. The scale `a`:
/// the largest elastic displacement of a node (see
/// [`Frames::elastic_amplitude`]) is [`MODE_AMPLITUDE`] × the longest
/// flexible body's length (an FE body's: its [`nodes_size`]); a mode
/// without elastic motion: its largest coordinate is [`MODE_AMPLITUDE`] ×
/// that length (m, or rad for angles).
/// Every file is checked ([`check_ours`]) before any is written.
pub fn write_linear_modes(
    dir: &Path,
    name: &str,
    scene: &Scene,
    q0: &[f64],
    modes: &[(f64, &ModeVector)],
) -> crate::Result<Vec<VtkWritten>> {
    let name = series_name(name);
    let (stem, frame_file) = mode_names(&name, modes.len());
    check_mode_files(dir, &name, modes.len())?;
    let mut length = scene
        .flex
        .iter()
        .map(|f| f.params.length)
        .fold(0.0f64, f64::max);
    for e in scene.system.bodies() {
        if e.body.node_count() > 0 {
            length = length.max(nodes_size(e.body.as_ref())?);
        }
    }
    let length = if length > 0.0 { length } else { 1.0 };
    let mut frames = Frames::new(&scene.system, drawing(scene)?);
    let n = q0.len();
    let mut written = Vec::with_capacity(modes.len());
    for (j, (omega, vector)) in modes.iter().enumerate() {
        let mut v = vec![Complex::new(0.0, 0.0); n];
        for &(g, x) in vector.iter() {
            if g < n {
                v[g] = x;
            }
        }
        let m = frames.elastic_amplitude(&v);
        let biggest = v.iter().map(|x| x.norm()).fold(0.0f64, f64::max);
        let a = if m > 0.0 {
            MODE_AMPLITUDE * length / m
        } else if biggest > 0.0 {
            MODE_AMPLITUDE * length / biggest
        } else {
            0.0
        };
        let period = if *omega > 0.0 && omega.is_finite() {
            std::f64::consts::TAU / omega
        } else {
            1.0
        };
        let mut steps = Vec::with_capacity(FRAMES_PER_PERIOD);
        let mut q = q0.to_vec();
        for k in 0..FRAMES_PER_PERIOD {
            let phase = std::f64::consts::TAU * k as f64 / FRAMES_PER_PERIOD as f64;
            let e = Complex::new(phase.cos(), phase.sin());
            for (i, x) in v.iter().enumerate() {
                q[i] = q0[i] + a * (e * x).re;
            }
            let file = frame_file(j, k);
            write_atomic(&dir.join(&file), &vtp_text(frames.piece(&q))?)?;
            steps.push((period * k as f64 / FRAMES_PER_PERIOD as f64, file));
        }
        let pvd = dir.join(format!("{}.pvd", stem(j)));
        write_atomic(&pvd, &pvd_text(&steps)?)?;
        written.push(VtkWritten {
            pvd,
            steps: steps.into_iter().map(|(t, f)| (t, dir.join(f))).collect(),
        });
    }
    Ok(written)
}
