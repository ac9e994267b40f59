//! A scene as resolved data: what a scene file says once it is read and
//! checked (names looked up, markers parsed, profiles and motors chosen,
//! defaults filled in), before anything is built from it.
//!
//! The scene loader produces it from a file; a compiled scene carries it as
//! generated data (no file is parsed at start-up); the library builds the
//! runtime system from it. Every part keeps the [`Location`] of what it came
//! from, so that what only the build can refuse (a joint that does not
//! close, a parameter the body's kernels need) is still reported at
//! `file:line:column`.

use crate::{KernelOptions, Location, Params, Reference};

/// The most values a scene run records (`t` and every output at every
/// step), checked when a scene is resolved: 2²⁵ values (256 MiB as numbers,
/// about 0.7 GB as CSV text).
pub const MAX_RECORDED_VALUES: usize = 1 << 25;

/// A scene, resolved.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSpec {
    /// The file it came from (as named).
    pub origin: String,
    /// Its description line, if any.
    pub description: Option<String>,
    /// 2 (planar) or 3 (spatial).
    pub dim: usize,
    /// End time (s).
    pub t_end: f64,
    /// Step (s).
    pub dt: f64,
    /// Where `dt` is written (the initial state's refusals point here when
    /// no joint is to blame).
    pub dt_at: Location,
    /// The integrator and its settings.
    pub integrator: IntegratorSpec,
    /// Gravity (m/s², zero-padded to 3 components) and where it is written.
    pub gravity: Option<([f64; 3], Location)>,
    /// The bodies, in file order (name order).
    pub bodies: Vec<BodySpec>,
    /// The joints, in file order.
    pub joints: Vec<JointSpec>,
    /// The forces, in file order.
    pub forces: Vec<ForceSpec>,
    /// The output columns after `t`, in file order.
    pub outputs: Vec<OutputSpec>,
    /// The named inputs (`[[inputs]]`), in file order.
    pub inputs: Vec<InputSpec>,
}

/// What a named input does.
#[derive(Clone, Debug, PartialEq)]
pub enum InputKind {
    /// A torque `u` (N m) in revolute joint `joint` (0-based in
    /// `[[joints]]`) about its axis: on its marker `b`, `−u` on `a`.
    Torque {
        /// The joint (0-based).
        joint: usize,
    },
    /// A force `u d` (N) at a marker along `direction` `d` as given (not
    /// normalized), in global axes or (`follower`) the body's.
    Force {
        /// Where it acts.
        at: MarkerSpec,
        /// The force per unit input (zero-padded).
        direction: [f64; 3],
        /// In the body's axes.
        follower: bool,
    },
    /// An acceleration `u` (rad/s², m/s²) added to joint `joint`'s drive:
    /// `φ = φ_drive(t) + δ(t)`, `δ̈ = u` held over each step.
    DriveAcceleration {
        /// The joint (0-based).
        joint: usize,
    },
}

/// A named input (`[[inputs]]`): a value a caller sets between steps,
/// held over each step (zero-order hold).
#[derive(Clone, Debug, PartialEq)]
pub struct InputSpec {
    /// Its name.
    pub name: String,
    /// What it does.
    pub kind: InputKind,
    /// Its value until a caller or the profile sets another.
    pub start: f64,
    /// Its value at each step's start when no caller sets it.
    pub profile: Option<ForceProfile>,
    /// Where its table is.
    pub at: Location,
}

/// The integrator; a setting left out keeps the runtime's default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum IntegratorSpec {
    /// Implicit generalized-α.
    GeneralizedAlpha {
        /// Spectral radius at infinity, in [0, 1].
        rho_inf: Option<f64>,
        /// Relative Newton tolerance, in (0, 1).
        rtol: Option<f64>,
    },
    /// Explicit RK4 with Baumgarte stabilization.
    Rk4 {
        /// Baumgarte's α.
        alpha: Option<f64>,
        /// Baumgarte's β.
        beta: Option<f64>,
    },
}

impl Default for IntegratorSpec {
    fn default() -> Self {
        IntegratorSpec::GeneralizedAlpha {
            rho_inf: None,
            rtol: None,
        }
    }
}

/// A body.
#[derive(Clone, Debug, PartialEq)]
pub struct BodySpec {
    /// Its name (`[bodies.NAME]`).
    pub name: String,
    /// Where its table is.
    pub at: Location,
    /// Rigid or flexible.
    pub kind: BodyKind,
    /// Frame position (zero-padded to 3 components).
    pub position: [f64; 3],
    /// Frame orientation.
    pub orientation: Orientation,
    /// Rayleigh damping `alpha M + beta K` of the elastic coordinates, and
    /// where it is written.
    pub damping: Option<(f64, f64, Location)>,
    /// Initial frame velocity (global, zero-padded).
    pub velocity: [f64; 3],
    /// Initial angular velocity (global; planar: about z).
    pub omega: [f64; 3],
    /// Initial elastic state by coordinate label.
    pub elastic: Option<ElasticSpec>,
}

/// A frame orientation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Orientation {
    /// Planar: an angle about z (rad).
    Planar(f64),
    /// Spatial: aligned with the global axes.
    Identity,
    /// Spatial: a rotation by `angle` (rad) about `axis` (not zero; need not
    /// be a unit vector).
    AxisAngle {
        /// The axis.
        axis: [f64; 3],
        /// The angle (rad).
        angle: f64,
    },
}

/// What a body is made of.
// Built once per scene and read once: the size of a variant does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum BodyKind {
    /// A rigid body.
    Rigid {
        /// Mass (kg, > 0).
        mass: f64,
        /// Inertia about the centre of mass (planar: `[[0, 0, 0], [0, 0, 0],
        /// [0, 0, J]]`).
        inertia: [[f64; 3]; 3],
        /// Centre of mass in the body frame (zero-padded).
        centre: [f64; 3],
    },
    /// A flexible body.
    Flexible(FlexSpec),
    /// A body from finite-element matrices (`fe = { nodes, mass, stiffness }`),
    /// always reduced to modes.
    Fe(FeSpec),
}

/// A body from finite-element matrices: the files (resolved against the
/// scene file's directory), the reference condition, the interface nodes
/// and the modal reduction. The files are read when the scene is built.
#[derive(Clone, Debug, PartialEq)]
pub struct FeSpec {
    /// The body's name.
    pub name: String,
    /// The node file (CSV `x,y,z`).
    pub nodes: String,
    /// The mass matrix (Matrix Market).
    pub mass: String,
    /// The stiffness matrix (Matrix Market).
    pub stiffness: String,
    /// `fe.stiffness_scale`: the factor the stiffness matrix is multiplied
    /// by (Young's modulus scaled, Poisson's ratio kept), 1 unless given.
    pub stiffness_scale: f64,
    /// Where `fe` is written.
    pub fe_at: Location,
    /// `true`: `reference = "free"`; `false`: `"clamped"` (the frame fixed
    /// to the interface nodes).
    pub free: bool,
    /// The interface nodes (0-based rows of the node file), as written.
    pub interface: Vec<usize>,
    /// Where `interface` is written (the `fe` key when it is not).
    pub interface_at: Location,
    /// The reduction (Craig–Bampton `boundary`: FE node indices), and where
    /// `modes` is written.
    pub modal: (ModalSettings, Location),
}

/// A flexible body: the beam, what the scene fixes for its kernels, and its
/// modal reduction, if any.
#[derive(Clone, Debug, PartialEq)]
pub struct FlexSpec {
    /// The body's name.
    pub name: String,
    /// The shape: a built-in name, or a file path resolved against the
    /// scene file's directory.
    pub shape: String,
    /// The shape as the scene file writes it (for messages).
    pub shape_name: String,
    /// Where the shape is written.
    pub shape_at: Location,
    /// Number of elements.
    pub elements: usize,
    /// A graded mesh: the `elements + 1` nodes' x, from 0 to the length
    /// (`None`: equal elements).
    pub nodes: Option<Vec<f64>>,
    /// How the frame is fixed to the body.
    pub reference: Reference,
    /// The kernel options (with what the scene fixes).
    pub options: KernelOptions,
    /// The parameters (those not given are zero).
    pub params: Params,
    /// Which of [`crate::Param::FIELDS`] the scene gives.
    pub given: [bool; 8],
    /// Where `params` is written.
    pub params_at: Location,
    /// A modal reduction, and where `modes` is written.
    pub modal: Option<(ModalSettings, Location)>,
    /// Section properties varying along the span (`sections = …`), instead
    /// of the uniform `params` (whose `length` is then the last station's x).
    pub sections: Option<SectionTable>,
    /// Masses attached on the axis (`[[bodies.NAME.masses]]`), in file order.
    pub masses: Vec<MassSpec>,
    /// The FFR sub-bodies it runs as (`segments = N`, 1: one floating
    /// frame); [`FlexSpec::segment`] gives each one's data.
    pub segments: usize,
    /// Where `segments` is written (`None`: not written, one segment).
    pub segments_at: Option<Location>,
}

/// A mass attached on a flexible body's axis, and where it is written.
#[derive(Clone, Debug, PartialEq)]
pub struct MassSpec {
    /// The mass.
    pub mass: crate::AttachedMass,
    /// Where it is written.
    pub at: Location,
}

/// A table of sections along a beam's span: every quantity varies linearly
/// in x between stations.
#[derive(Clone, Debug, PartialEq)]
pub struct SectionTable {
    /// The stations, x strictly increasing from 0 to the body's length.
    pub stations: Vec<Station>,
    /// Where the table is (a CSV file's path, or the scene's `sections`).
    pub at: Location,
}

/// One station of a [`SectionTable`], in the resultant form (SI units).
/// The material form `rho, area, iy, iz, e, g, j` is read into it as
/// `mass = ρA`, `ea = EA`, `ei_y = E I_y`, `ei_z = E I_z`, `gj = G J`,
/// `rho_iy = ρ I_y`, `rho_iz = ρ I_z`, `rho_j = ρ (I_y + I_z)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Station {
    /// m from the body's root.
    pub x: f64,
    /// Mass per length ρA (kg/m).
    pub mass: f64,
    /// Axial stiffness EA (N).
    pub ea: f64,
    /// Bending stiffness in the x–z plane (`w`), E I_y = ∫E z² dA (N m²),
    /// about the section's principal axes.
    pub ei_y: f64,
    /// Bending stiffness in the x–y plane (`v`), E I_z = ∫E y² dA (N m²).
    pub ei_z: f64,
    /// Torsional stiffness GJ (N m²).
    pub gj: f64,
    /// Section mass moment ρI_y = ∫ρ z² dA (kg m), principal axes.
    pub rho_iy: f64,
    /// Section mass moment ρI_z = ∫ρ y² dA (kg m).
    pub rho_iz: f64,
    /// Polar mass moment per length (kg m); `rho_iy + rho_iz` unless given.
    pub rho_j: f64,
    /// Angle of the principal axes about +x (rad), which couples the
    /// bending planes through `EI_yz` and `ρI_yz`.
    pub twist: f64,
}

/// How a flexible body is reduced.
#[derive(Clone, Debug, PartialEq)]
pub struct ModalSettings {
    /// Normal modes kept: the lowest eigenmodes (modal truncation) or
    /// fixed-interface modes (Craig–Bampton).
    pub modes: usize,
    /// Craig–Bampton boundary nodes; empty: modal truncation.
    pub boundary: Vec<usize>,
    /// Add the static modes (inertia loads of the frame's motion and, with
    /// stiffening, the modal derivatives).
    pub static_modes: bool,
    /// Damping ratios `ζ` of the normal modes: none, one for every normal
    /// mode, or one per normal mode; `D = diag(2 ζ_i ω_i)` on them (the other
    /// modes are undamped).
    pub damping: Vec<f64>,
}

impl ModalSettings {
    /// `modes` normal modes of a modal truncation with static modes, no damping.
    pub fn truncation(modes: usize) -> Self {
        Self {
            modes,
            boundary: Vec::new(),
            static_modes: true,
            damping: Vec::new(),
        }
    }
}

/// A flexible body's initial elastic state, by coordinate label (the
/// coordinates not named start at zero).
#[derive(Clone, Debug, PartialEq)]
pub struct ElasticSpec {
    /// Where `elastic` is written.
    pub at: Location,
    /// `q_f` entries: label, value, where the label is written.
    pub q: Vec<(String, f64, Location)>,
    /// `q̇_f` entries.
    pub qd: Vec<(String, f64, Location)>,
}

/// A marker as a scene writes it, with its text (for messages) and where it
/// is written.
#[derive(Clone, Debug, PartialEq)]
pub struct MarkerSpec {
    /// What it names.
    pub point: MarkerPoint,
    /// The text as written (`hub@[0.5, 0]`; of a table marker, its `at`).
    pub text: String,
    /// Where.
    pub at: Location,
    /// The marker's own axes (`{ at = "…", axes = { … } }`): the rotation
    /// `R` that turns the axes of its section, body or the ground (global
    /// axes) into the marker's; the marker's x, y, z are the columns of `R`
    /// in those axes. Planar: [`Orientation::Planar`] (a rotation about z);
    /// spatial: [`Orientation::AxisAngle`] (axis not zero, finite).
    /// `None`: the axes of the section, body or ground themselves.
    pub axes: Option<Orientation>,
}

/// The point a marker names (bodies by index in [`SceneSpec::bodies`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MarkerPoint {
    /// A point on the ground (`ground@[x, y]`).
    Ground([f64; 3]),
    /// A body's frame origin (`NAME`).
    Origin(usize),
    /// A point on a beam's axis (`NAME@x=…`).
    Axis(usize, f64),
    /// A point fixed in a body's frame (`NAME@[x, y]`).
    Point(usize, [f64; 3]),
    /// A node of an FE body (`NAME@node=N`, 0-based).
    Node(usize, usize),
}

/// A prescribed motion `f(t)` (an angle or a slide) with its rate and
/// acceleration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ProfileSpec {
    /// `start + ` the smooth spin-up to rate `omega` over `ramp` s.
    SpinUp {
        /// Final rate.
        omega: f64,
        /// Ramp time (s, > 0).
        ramp: f64,
        /// Value at `t = 0`.
        start: f64,
    },
    /// `start + rate t`.
    ConstantRate {
        /// Value at `t = 0`.
        start: f64,
        /// Rate.
        rate: f64,
    },
    /// A constant value.
    Constant(f64),
    /// `start + amplitude sin(2π frequency t + phase)`.
    Harmonic {
        /// Mean value.
        start: f64,
        /// Amplitude.
        amplitude: f64,
        /// Frequency (Hz).
        frequency: f64,
        /// Phase (rad).
        phase: f64,
    },
}

/// A joint's kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointKind {
    /// Fixes body `b`'s frame where it starts.
    Ground,
    /// Fixes `b` to `a`.
    Fixed,
    /// A hinge about z (planar) or about `a`'s z axis.
    Revolute,
    /// A ball joint (spatial).
    Spherical,
    /// A slider along `a`'s x axis.
    Prismatic,
}

impl JointKind {
    /// The kind as a scene file writes it (`revolute`).
    pub fn name(self) -> &'static str {
        match self {
            JointKind::Ground => "ground",
            JointKind::Fixed => "fixed",
            JointKind::Revolute => "revolute",
            JointKind::Spherical => "spherical",
            JointKind::Prismatic => "prismatic",
        }
    }
}

/// A motor in a revolute joint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MotorSpec {
    /// A constant torque (N m).
    Torque(f64),
    /// A PD law towards a target angle.
    Pd {
        /// The target angle.
        target: ProfileSpec,
        /// Stiffness gain (N m/rad, ≥ 0).
        kp: f64,
        /// Damping gain (N m s/rad, ≥ 0).
        kd: f64,
    },
}

/// A joint.
#[derive(Clone, Debug, PartialEq)]
pub struct JointSpec {
    /// Its kind.
    pub kind: JointKind,
    /// Where the joint's table is.
    pub at: Location,
    /// Where `kind` is written.
    pub kind_at: Location,
    /// Marker `a` (none for a ground joint).
    pub a: Option<MarkerSpec>,
    /// Marker `b`.
    pub b: MarkerSpec,
    /// A drive (revolute: angle; prismatic: slide), and where it is written.
    pub drive: Option<(ProfileSpec, Location)>,
    /// A motor (revolute), and where it is written.
    pub motor: Option<(MotorSpec, Location)>,
    /// `Some(body)`: a revolute joint to the ground at the body's frame
    /// origin with an angle drive, folded into the body's prescribed frame
    /// coordinates.
    pub folds: Option<usize>,
}

/// What a force does.
#[derive(Clone, Debug, PartialEq)]
pub enum ForceKind {
    /// A force at a marker (N), in global axes or (`follower`) in the body's.
    Point {
        /// Where it acts.
        at: MarkerSpec,
        /// The force (zero-padded).
        force: [f64; 3],
        /// In the body's axes (a follower force).
        follower: bool,
        /// A time function `f(t)` scaling the force, `F(t) = f(t) force`
        /// (`profile = { … }`); `None`: `F = force` at all times.
        profile: Option<ForceProfile>,
    },
    /// A linear spring-damper between two markers.
    SpringDamper {
        /// End `a`.
        a: MarkerSpec,
        /// End `b`.
        b: MarkerSpec,
        /// N/m.
        stiffness: f64,
        /// N s/m.
        damping: f64,
        /// m.
        rest_length: f64,
    },
    /// A rotational spring-damper about the relative angle of two markers.
    RotationalSpringDamper {
        /// End `a`.
        a: MarkerSpec,
        /// End `b`.
        b: MarkerSpec,
        /// N m/rad.
        stiffness: f64,
        /// N m s/rad.
        damping: f64,
        /// rad.
        rest_angle: f64,
    },
    /// A constant torque between two markers (N m).
    Torque {
        /// End `a`.
        a: MarkerSpec,
        /// End `b`.
        b: MarkerSpec,
        /// N m.
        torque: f64,
    },
}

/// The most rows of a point force's `profile = { table = … }`, checked
/// while the table is read (before more is stored).
pub const MAX_PROFILE_ROWS: usize = 100_000;

/// The largest coordinate of a position in a scene file (a body's
/// `position`, a point of a marker), in m: f64 resolves about 1e-7 m at
/// 1e9 m, and a joint between points far from the origin loses the motion
/// to round-off (a ground point at −1e308 gave "a body's rotation is
/// constrained twice", or a run whose positions never changed).
pub const MAX_COORDINATE: f64 = 1e9;

/// The time function `f(t)` of a point force's `profile`.
#[derive(Clone, Debug, PartialEq)]
pub enum ForceProfile {
    /// The value `f(t)` of a drive profile (`kind = "harmonic"`, …).
    Drive(ProfileSpec),
    /// Piecewise linear through the rows `[t_i, f_i]` (times strictly
    /// increasing, all finite, 1 to [`MAX_PROFILE_ROWS`] rows): `f_0` before
    /// `t_0`, the last value after the last time, linear in between.
    Table(Vec<[f64; 2]>),
}

/// A force, and where its table is.
#[derive(Clone, Debug, PartialEq)]
pub struct ForceSpec {
    /// What it does.
    pub kind: ForceKind,
    /// Where.
    pub at: Location,
}

/// What an output column records.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputKind {
    /// Global position of a marker (component 0, 1, 2).
    Position(usize),
    /// Elastic displacement of a marker in its body's frame.
    Deflection(usize),
    /// Global velocity of a marker.
    Velocity(usize),
    /// The angle of the marker's x axis in the global x–y plane, or, with a
    /// reference marker `a`, about `a`'s z axis (`atan2(x·y_a, x·x_a)`),
    /// unwrapped along the run.
    Angle,
    /// An energy: total, kinetic, elastic, gravity or springs; or the
    /// work done on the system so far by point forces and motors, or taken
    /// out by dampers (trapezoidal rule over the steps).
    Energy(EnergyPart),
}

/// Which energy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnergyPart {
    /// `T + V`.
    Total,
    /// `T`.
    Kinetic,
    /// Elastic.
    Elastic,
    /// Gravitational.
    Gravity,
    /// Springs.
    Springs,
    /// `∫ P_applied dt`: work of the point forces and motors since `t = 0`.
    Work,
    /// `∫ P_dissipated dt`: energy taken out by the dampers since `t = 0`.
    Dissipated,
}

/// An output column.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputSpec {
    /// Column name (checked: a CSV column, not `t`, not repeated).
    pub name: String,
    /// What it records.
    pub kind: OutputKind,
    /// Where (none for energies).
    pub at: Option<MarkerSpec>,
    /// Reference marker of a relative angle.
    pub relative_to: Option<MarkerSpec>,
}
