//! A resolved scene as Rust: the expression that rebuilds a [`SceneSpec`]
//! value, so that a compiled scene carries its scene as data (no file is
//! parsed at start-up). Floats are written with Rust's shortest round-trip
//! form, so the value rebuilt is bit-identical to the one resolved; strings
//! are escaped by `{:?}`, so no user text reaches the generated code
//! unescaped.

use ffr_spec::scene::{
    BodyKind, BodySpec, ElasticSpec, ForceKind, ForceProfile, ForceSpec, InputKind, InputSpec,
    IntegratorSpec, JointSpec, MarkerPoint, MarkerSpec, ModalSettings, MotorSpec, Orientation,
    OutputKind, OutputSpec, ProfileSpec, SceneSpec,
};
use ffr_spec::Location;

/// Where the generated expression finds things: `ffr_spec`'s path (shown
/// by `Display`, e.g. `::ffr::runtime::spec`) and the expression that names
/// the scene file (locations in it refer to that constant).
struct Ctx<'a> {
    spec: &'a str,
    origin: (&'a str, &'a str),
}

impl std::fmt::Display for Ctx<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.spec)
    }
}

/// Writes a value as a Rust expression.
trait Bake {
    fn bake(&self, s: &Ctx) -> String;
}

impl Bake for f64 {
    fn bake(&self, _: &Ctx) -> String {
        if self.is_nan() {
            "f64::NAN".into()
        } else if self.is_infinite() {
            if *self > 0.0 {
                "f64::INFINITY"
            } else {
                "f64::NEG_INFINITY"
            }
            .into()
        } else {
            // `{:?}` is the shortest form that reads back to the same bits
            // and always has a `.` or an exponent (a float literal).
            format!("{self:?}f64")
        }
    }
}

impl Bake for usize {
    fn bake(&self, _: &Ctx) -> String {
        format!("{self}usize")
    }
}

impl Bake for bool {
    fn bake(&self, _: &Ctx) -> String {
        self.to_string()
    }
}

impl Bake for String {
    fn bake(&self, _: &Ctx) -> String {
        format!("::std::string::String::from({self:?})")
    }
}

impl<T: Bake, const N: usize> Bake for [T; N] {
    fn bake(&self, s: &Ctx) -> String {
        let items: Vec<String> = self.iter().map(|x| x.bake(s)).collect();
        format!("[{}]", items.join(", "))
    }
}

impl<T: Bake> Bake for Vec<T> {
    /// `Vec::from([…])`, not `vec![…]`: a call, which the formatter lays
    /// out (it leaves macro arguments as they are).
    fn bake(&self, s: &Ctx) -> String {
        if self.is_empty() {
            return "::std::vec::Vec::new()".into();
        }
        let items: Vec<String> = self.iter().map(|x| x.bake(s)).collect();
        format!("::std::vec::Vec::from([{}])", items.join(", "))
    }
}

impl<T: Bake> Bake for Option<T> {
    fn bake(&self, s: &Ctx) -> String {
        match self {
            None => "::core::option::Option::None".into(),
            Some(x) => format!("::core::option::Option::Some({})", x.bake(s)),
        }
    }
}

impl<A: Bake, B: Bake> Bake for (A, B) {
    fn bake(&self, s: &Ctx) -> String {
        format!("({}, {})", self.0.bake(s), self.1.bake(s))
    }
}

impl<A: Bake, B: Bake, C: Bake> Bake for (A, B, C) {
    fn bake(&self, s: &Ctx) -> String {
        format!(
            "({}, {}, {})",
            self.0.bake(s),
            self.1.bake(s),
            self.2.bake(s)
        )
    }
}

impl Bake for Location {
    fn bake(&self, s: &Ctx) -> String {
        let file = if self.file == s.origin.0 {
            format!("::std::string::String::from({})", s.origin.1)
        } else {
            self.file.bake(s)
        };
        format!(
            "{s}::Location {{ file: {file}, line: {}, column: {} }}",
            self.line.bake(s),
            self.column.bake(s)
        )
    }
}

/// A unit variant of an `ffr_spec` enum by its `Debug` name (the variant's
/// name), under `path`.
fn unit(s: &Ctx, path: &str, v: &impl std::fmt::Debug) -> String {
    format!("{s}::{path}::{v:?}")
}

impl Bake for IntegratorSpec {
    fn bake(&self, s: &Ctx) -> String {
        match self {
            IntegratorSpec::GeneralizedAlpha { rho_inf, rtol } => format!(
                "{s}::scene::IntegratorSpec::GeneralizedAlpha {{ rho_inf: {}, rtol: {} }}",
                rho_inf.bake(s),
                rtol.bake(s)
            ),
            IntegratorSpec::Rk4 { alpha, beta } => format!(
                "{s}::scene::IntegratorSpec::Rk4 {{ alpha: {}, beta: {} }}",
                alpha.bake(s),
                beta.bake(s)
            ),
        }
    }
}

impl Bake for Orientation {
    fn bake(&self, s: &Ctx) -> String {
        match self {
            Orientation::Planar(a) => format!("{s}::scene::Orientation::Planar({})", a.bake(s)),
            Orientation::Identity => format!("{s}::scene::Orientation::Identity"),
            Orientation::AxisAngle { axis, angle } => format!(
                "{s}::scene::Orientation::AxisAngle {{ axis: {}, angle: {} }}",
                axis.bake(s),
                angle.bake(s)
            ),
        }
    }
}

impl Bake for ModalSettings {
    fn bake(&self, s: &Ctx) -> String {
        format!(
            "{s}::scene::ModalSettings {{ modes: {}, boundary: {}, static_modes: {}, damping: {} }}",
            self.modes.bake(s),
            self.boundary.bake(s),
            self.static_modes.bake(s),
            self.damping.bake(s)
        )
    }
}

impl Bake for ffr_spec::scene::FlexSpec {
    fn bake(&self, s: &Ctx) -> String {
        let o = &self.options;
        let options = format!(
            "{s}::KernelOptions {{ formalism: {}, stiffening: {}, scene: {}, frame: {} }}",
            unit(s, "Formalism", &o.formalism),
            unit(s, "Stiffening", &o.stiffening),
            match o.scene {
                None => "::core::option::Option::None".to_string(),
                Some(d) => format!("::core::option::Option::Some({})", unit(s, "SceneDim", &d)),
            },
            unit(s, "FrameModel", &o.frame),
        );
        format!(
            "{s}::scene::FlexSpec {{ name: {}, shape: {}, shape_name: {}, shape_at: {}, elements: {}, nodes: {}, reference: {}, options: {options}, params: {s}::Params::from_array({}), given: {}, params_at: {}, modal: {}, sections: {}, masses: {}, segments: {}, segments_at: {} }}",
            self.name.bake(s),
            self.shape.bake(s),
            self.shape_name.bake(s),
            self.shape_at.bake(s),
            self.elements.bake(s),
            self.nodes.bake(s),
            unit(s, "Reference", &self.reference),
            self.params.to_array().bake(s),
            self.given.bake(s),
            self.params_at.bake(s),
            self.modal.bake(s),
            self.sections.bake(s),
            self.masses.bake(s),
            self.segments.bake(s),
            self.segments_at.bake(s)
        )
    }
}

impl Bake for ffr_spec::scene::FeSpec {
    fn bake(&self, s: &Ctx) -> String {
        format!(
            "{s}::scene::FeSpec {{ name: {}, nodes: {}, mass: {}, stiffness: {}, stiffness_scale: {}, fe_at: {}, free: {}, interface: {}, interface_at: {}, modal: {} }}",
            self.name.bake(s),
            self.nodes.bake(s),
            self.mass.bake(s),
            self.stiffness.bake(s),
            self.stiffness_scale.bake(s),
            self.fe_at.bake(s),
            self.free.bake(s),
            self.interface.bake(s),
            self.interface_at.bake(s),
            self.modal.bake(s)
        )
    }
}

impl Bake for BodyKind {
    fn bake(&self, s: &Ctx) -> String {
        match self {
            BodyKind::Rigid {
                mass,
                inertia,
                centre,
            } => format!(
                "{s}::scene::BodyKind::Rigid {{ mass: {}, inertia: {}, centre: {} }}",
                mass.bake(s),
                inertia.bake(s),
                centre.bake(s)
            ),
            BodyKind::Flexible(f) => format!("{s}::scene::BodyKind::Flexible({})", f.bake(s)),
            BodyKind::Fe(f) => format!("{s}::scene::BodyKind::Fe({})", f.bake(s)),
        }
    }
}

impl Bake for ElasticSpec {
    fn bake(&self, s: &Ctx) -> String {
        format!(
            "{s}::scene::ElasticSpec {{ at: {}, q: {}, qd: {} }}",
            self.at.bake(s),
            self.q.bake(s),
            self.qd.bake(s)
        )
    }
}

impl Bake for BodySpec {
    fn bake(&self, s: &Ctx) -> String {
        format!(
            "{s}::scene::BodySpec {{ name: {}, at: {}, kind: {}, position: {}, orientation: {}, damping: {}, velocity: {}, omega: {}, elastic: {} }}",
            self.name.bake(s),
            self.at.bake(s),
            self.kind.bake(s),
            self.position.bake(s),
            self.orientation.bake(s),
            self.damping.bake(s),
            self.velocity.bake(s),
            self.omega.bake(s),
            self.elastic.bake(s)
        )
    }
}

impl Bake for MarkerSpec {
    fn bake(&self, s: &Ctx) -> String {
        let point = match &self.point {
            MarkerPoint::Ground(p) => format!("{s}::scene::MarkerPoint::Ground({})", p.bake(s)),
            MarkerPoint::Origin(b) => format!("{s}::scene::MarkerPoint::Origin({})", b.bake(s)),
            MarkerPoint::Axis(b, x) => format!(
                "{s}::scene::MarkerPoint::Axis({}, {})",
                b.bake(s),
                x.bake(s)
            ),
            MarkerPoint::Point(b, p) => format!(
                "{s}::scene::MarkerPoint::Point({}, {})",
                b.bake(s),
                p.bake(s)
            ),
            MarkerPoint::Node(b, n) => format!(
                "{s}::scene::MarkerPoint::Node({}, {})",
                b.bake(s),
                n.bake(s)
            ),
        };
        format!(
            "{s}::scene::MarkerSpec {{ point: {point}, text: {}, at: {}, axes: {} }}",
            self.text.bake(s),
            self.at.bake(s),
            self.axes.bake(s)
        )
    }
}

impl Bake for ProfileSpec {
    fn bake(&self, s: &Ctx) -> String {
        match self {
            ProfileSpec::SpinUp { omega, ramp, start } => format!(
                "{s}::scene::ProfileSpec::SpinUp {{ omega: {}, ramp: {}, start: {} }}",
                omega.bake(s),
                ramp.bake(s),
                start.bake(s)
            ),
            ProfileSpec::ConstantRate { start, rate } => format!(
                "{s}::scene::ProfileSpec::ConstantRate {{ start: {}, rate: {} }}",
                start.bake(s),
                rate.bake(s)
            ),
            ProfileSpec::Constant(v) => format!("{s}::scene::ProfileSpec::Constant({})", v.bake(s)),
            ProfileSpec::Harmonic {
                start,
                amplitude,
                frequency,
                phase,
            } => format!(
                "{s}::scene::ProfileSpec::Harmonic {{ start: {}, amplitude: {}, frequency: {}, phase: {} }}",
                start.bake(s),
                amplitude.bake(s),
                frequency.bake(s),
                phase.bake(s)
            ),
        }
    }
}

impl Bake for ForceProfile {
    fn bake(&self, s: &Ctx) -> String {
        match self {
            ForceProfile::Drive(p) => format!("{s}::scene::ForceProfile::Drive({})", p.bake(s)),
            ForceProfile::Table(rows) => {
                format!("{s}::scene::ForceProfile::Table({})", rows.bake(s))
            }
        }
    }
}

impl Bake for MotorSpec {
    fn bake(&self, s: &Ctx) -> String {
        match self {
            MotorSpec::Torque(t) => format!("{s}::scene::MotorSpec::Torque({})", t.bake(s)),
            MotorSpec::Pd { target, kp, kd } => format!(
                "{s}::scene::MotorSpec::Pd {{ target: {}, kp: {}, kd: {} }}",
                target.bake(s),
                kp.bake(s),
                kd.bake(s)
            ),
        }
    }
}

impl Bake for JointSpec {
    fn bake(&self, s: &Ctx) -> String {
        format!(
            "{s}::scene::JointSpec {{ kind: {}, at: {}, kind_at: {}, a: {}, b: {}, drive: {}, motor: {}, folds: {} }}",
            unit(s, "scene::JointKind", &self.kind),
            self.at.bake(s),
            self.kind_at.bake(s),
            self.a.bake(s),
            self.b.bake(s),
            self.drive.bake(s),
            self.motor.bake(s),
            self.folds.bake(s)
        )
    }
}

impl Bake for ForceSpec {
    fn bake(&self, s: &Ctx) -> String {
        let kind = match &self.kind {
            ForceKind::Point {
                at,
                force,
                follower,
                profile,
            } => format!(
                "{s}::scene::ForceKind::Point {{ at: {}, force: {}, follower: {}, profile: {} }}",
                at.bake(s),
                force.bake(s),
                follower.bake(s),
                profile.bake(s)
            ),
            ForceKind::SpringDamper {
                a,
                b,
                stiffness,
                damping,
                rest_length,
            } => format!(
                "{s}::scene::ForceKind::SpringDamper {{ a: {}, b: {}, stiffness: {}, damping: {}, rest_length: {} }}",
                a.bake(s),
                b.bake(s),
                stiffness.bake(s),
                damping.bake(s),
                rest_length.bake(s)
            ),
            ForceKind::RotationalSpringDamper {
                a,
                b,
                stiffness,
                damping,
                rest_angle,
            } => format!(
                "{s}::scene::ForceKind::RotationalSpringDamper {{ a: {}, b: {}, stiffness: {}, damping: {}, rest_angle: {} }}",
                a.bake(s),
                b.bake(s),
                stiffness.bake(s),
                damping.bake(s),
                rest_angle.bake(s)
            ),
            ForceKind::Torque { a, b, torque } => format!(
                "{s}::scene::ForceKind::Torque {{ a: {}, b: {}, torque: {} }}",
                a.bake(s),
                b.bake(s),
                torque.bake(s)
            ),
        };
        format!(
            "{s}::scene::ForceSpec {{ kind: {kind}, at: {} }}",
            self.at.bake(s)
        )
    }
}

impl Bake for OutputSpec {
    fn bake(&self, s: &Ctx) -> String {
        let kind = match &self.kind {
            OutputKind::Position(c) => format!("{s}::scene::OutputKind::Position({})", c.bake(s)),
            OutputKind::Deflection(c) => {
                format!("{s}::scene::OutputKind::Deflection({})", c.bake(s))
            }
            OutputKind::Velocity(c) => format!("{s}::scene::OutputKind::Velocity({})", c.bake(s)),
            OutputKind::Angle => format!("{s}::scene::OutputKind::Angle"),
            OutputKind::Energy(p) => format!(
                "{s}::scene::OutputKind::Energy({})",
                unit(s, "scene::EnergyPart", p)
            ),
        };
        format!(
            "{s}::scene::OutputSpec {{ name: {}, kind: {kind}, at: {}, relative_to: {} }}",
            self.name.bake(s),
            self.at.bake(s),
            self.relative_to.bake(s)
        )
    }
}

/// The Rust expression that rebuilds `scene`, with `ffr_spec` at `spec_path`
/// (e.g. `::ffr::runtime::spec`) and the scene file's name as written by
/// the expression `origin` (e.g. `Self::ORIGIN`; it must equal
/// `scene.origin`).
pub fn scene_expr(scene: &SceneSpec, spec_path: &str, origin: &str) -> String {
    let s = &Ctx {
        spec: spec_path,
        origin: (&scene.origin, origin),
    };
    format!(
        "{s}::scene::SceneSpec {{ origin: ::std::string::String::from({}), description: {}, dim: {}, t_end: {}, dt: {}, dt_at: {}, integrator: {}, gravity: {}, bodies: {}, joints: {}, forces: {}, outputs: {}, inputs: {} }}",
        origin,
        scene.description.bake(s),
        scene.dim.bake(s),
        scene.t_end.bake(s),
        scene.dt.bake(s),
        scene.dt_at.bake(s),
        scene.integrator.bake(s),
        scene.gravity.bake(s),
        scene.bodies.bake(s),
        scene.joints.bake(s),
        scene.forces.bake(s),
        scene.outputs.bake(s),
        scene.inputs.bake(s)
    )
}

impl Bake for InputSpec {
    fn bake(&self, s: &Ctx) -> String {
        let kind = match &self.kind {
            InputKind::Torque { joint } => {
                format!(
                    "{s}::scene::InputKind::Torque {{ joint: {} }}",
                    joint.bake(s)
                )
            }
            InputKind::DriveAcceleration { joint } => format!(
                "{s}::scene::InputKind::DriveAcceleration {{ joint: {} }}",
                joint.bake(s)
            ),
            InputKind::Force {
                at,
                direction,
                follower,
            } => format!(
                "{s}::scene::InputKind::Force {{ at: {}, direction: {}, follower: {} }}",
                at.bake(s),
                direction.bake(s),
                follower.bake(s)
            ),
        };
        format!(
            "{s}::scene::InputSpec {{ name: {}, kind: {kind}, start: {}, profile: {}, at: {} }}",
            self.name.bake(s),
            self.start.bake(s),
            self.profile.bake(s),
            self.at.bake(s)
        )
    }
}

impl Bake for ffr_spec::scene::Station {
    fn bake(&self, s: &Ctx) -> String {
        format!(
            "{s}::scene::Station {{ x: {}, mass: {}, ea: {}, ei_y: {}, ei_z: {}, gj: {}, rho_iy: {}, rho_iz: {}, rho_j: {}, twist: {} }}",
            self.x.bake(s),
            self.mass.bake(s),
            self.ea.bake(s),
            self.ei_y.bake(s),
            self.ei_z.bake(s),
            self.gj.bake(s),
            self.rho_iy.bake(s),
            self.rho_iz.bake(s),
            self.rho_j.bake(s),
            self.twist.bake(s)
        )
    }
}

impl Bake for ffr_spec::scene::SectionTable {
    fn bake(&self, s: &Ctx) -> String {
        format!(
            "{s}::scene::SectionTable {{ stations: {}, at: {} }}",
            self.stations.bake(s),
            self.at.bake(s)
        )
    }
}

impl Bake for ffr_spec::scene::MassSpec {
    fn bake(&self, s: &Ctx) -> String {
        let m = &self.mass;
        format!(
            "{s}::scene::MassSpec {{ mass: {s}::AttachedMass {{ x: {}, mass: {}, inertia: {} }}, at: {} }}",
            m.x.bake(s),
            m.mass.bake(s),
            m.inertia.bake(s),
            self.at.bake(s)
        )
    }
}
