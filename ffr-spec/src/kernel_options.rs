//! The options a set of element kernels is generated for, as one value
//! ([`KernelOptions`]): carried unchanged from a command line, a scene file,
//! the `#[flex_body]` attribute or a build script down to the generator's
//! kernel model and the runtime's kernel info.

use crate::{Formalism, Stiffening};
use std::fmt;
use std::str::FromStr;

/// The scene a body moves in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SceneDim {
    /// Frame motion in the x–y plane (`ā_z = α_x = α_y = ω_x = ω_y = 0`).
    Planar,
    /// Any frame motion.
    Spatial,
}

impl SceneDim {
    /// Both scenes, with their names.
    pub const ALL: [(SceneDim, &'static str); 2] =
        [(SceneDim::Planar, "planar"), (SceneDim::Spatial, "spatial")];

    /// 2 (planar) or 3 (spatial).
    pub const fn dim(self) -> usize {
        match self {
            SceneDim::Planar => 2,
            SceneDim::Spatial => 3,
        }
    }

    /// The scene of dimension 2 or 3; `None` for any other number.
    pub const fn from_dim(d: usize) -> Option<Self> {
        match d {
            2 => Some(SceneDim::Planar),
            3 => Some(SceneDim::Spatial),
            _ => None,
        }
    }
}

impl FromStr for SceneDim {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        SceneDim::ALL
            .iter()
            .find(|(_, n)| *n == s)
            .map(|(d, _)| *d)
            .ok_or_else(|| format!("unknown scene `{s}`: expected planar or spatial"))
    }
}

impl fmt::Display for SceneDim {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            SceneDim::Planar => "planar",
            SceneDim::Spatial => "spatial",
        })
    }
}

/// What the kernels of a body assume about its frame's motion.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FrameModel {
    /// Any frame motion (reference rows, `ā` terms): the general body.
    #[default]
    Free,
    /// Frame motion prescribed (no reference rows); built-in shapes run the
    /// general compiled kernels, shape files tapes without reference rows.
    Prescribed,
    /// Frame motion prescribed, origin at rest, no gravity (`ā ≡ 0`).
    PrescribedAtRest,
}

impl FrameModel {
    /// Whether the reference rows (`f_r`, `f_θ`, `residual`, `tangent`) and
    /// the frame derivatives are generated: without them only a body whose
    /// frame motion is prescribed can use the kernels.
    pub const fn is_free(self) -> bool {
        matches!(self, FrameModel::Free)
    }

    /// Whether `ā = Aᵀ(R̈ − g) ≡ 0` (frame origin at rest or moving
    /// uniformly, no gravity): the kernels ignore `ā`, so the system refuses
    /// them where `ā` can be non-zero.
    pub const fn zero_frame_acceleration(self) -> bool {
        matches!(self, FrameModel::PrescribedAtRest)
    }

    /// `(free_frame, zero_frame_acceleration)`.
    pub const fn flags(self) -> (bool, bool) {
        (self.is_free(), self.zero_frame_acceleration())
    }

    /// From `(free_frame, zero_frame_acceleration)`; a free frame has `ā`
    /// terms whatever the second flag says.
    pub const fn from_flags(free_frame: bool, zero_frame_acceleration: bool) -> Self {
        match (free_frame, zero_frame_acceleration) {
            (true, _) => FrameModel::Free,
            (false, false) => FrameModel::Prescribed,
            (false, true) => FrameModel::PrescribedAtRest,
        }
    }
}

/// The options of one set of element kernels, besides the shape.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct KernelOptions {
    /// Inertia formalism (default consistent).
    pub formalism: Formalism,
    /// Stiffening model (default off).
    pub stiffening: Stiffening,
    /// The scene the body moves in; `None`: the shape's dimension.
    pub scene: Option<SceneDim>,
    /// What the kernels assume about the frame's motion (default free).
    pub frame: FrameModel,
}

impl KernelOptions {
    /// Consistent, no stiffening, the shape's scene, free frame.
    pub const fn new() -> Self {
        Self {
            formalism: Formalism::Consistent,
            stiffening: Stiffening::Off,
            scene: None,
            frame: FrameModel::Free,
        }
    }

    /// With this inertia formalism.
    pub const fn formalism(mut self, f: Formalism) -> Self {
        self.formalism = f;
        self
    }

    /// With this stiffening model.
    pub const fn stiffening(mut self, s: Stiffening) -> Self {
        self.stiffening = s;
        self
    }

    /// In this scene.
    pub const fn scene(mut self, d: SceneDim) -> Self {
        self.scene = Some(d);
        self
    }

    /// With this frame model.
    pub const fn frame(mut self, f: FrameModel) -> Self {
        self.frame = f;
        self
    }

    /// The scene, `None` resolved to a shape of dimension `shape_dim` (2 or 3).
    pub const fn scene_or(self, shape_dim: usize) -> SceneDim {
        match self.scene {
            Some(d) => d,
            None if shape_dim == 2 => SceneDim::Planar,
            None => SceneDim::Spatial,
        }
    }

    /// These options with the scene resolved for a shape of dimension
    /// `shape_dim`.
    pub const fn resolved(self, shape_dim: usize) -> Self {
        self.scene(self.scene_or(shape_dim))
    }

    /// One line for headers and docs: `consistent formalism, stiffening off,
    /// planar scene, free frame` (the scene as `shape's scene` while unresolved).
    pub fn describe(&self) -> String {
        format!(
            "{} formalism, stiffening {}, {} scene, {}",
            self.formalism,
            self.stiffening,
            self.scene.map_or("shape's".to_string(), |d| d.to_string()),
            if self.frame.is_free() {
                "free frame"
            } else {
                "prescribed frame motion"
            }
        )
    }
}

#[cfg(feature = "clap")]
mod value_enums {
    //! `clap::ValueEnum` for the options, with the names their `FromStr`
    //! accepts (`--stiffening on` is `fourth-order`).
    use crate::{Formalism, Reference, SceneDim, Stiffening};
    use clap::builder::PossibleValue;
    use clap::ValueEnum;

    impl ValueEnum for Formalism {
        fn value_variants<'a>() -> &'a [Self] {
            &[Formalism::Consistent, Formalism::Lumped]
        }
        fn to_possible_value(&self) -> Option<PossibleValue> {
            Some(PossibleValue::new(match self {
                Formalism::Consistent => "consistent",
                Formalism::Lumped => "lumped",
            }))
        }
    }

    impl ValueEnum for Stiffening {
        fn value_variants<'a>() -> &'a [Self] {
            &[
                Stiffening::Off,
                Stiffening::SecondOrder,
                Stiffening::FourthOrder,
            ]
        }
        fn to_possible_value(&self) -> Option<PossibleValue> {
            Some(match self {
                Stiffening::Off => PossibleValue::new("off").alias("false"),
                Stiffening::SecondOrder => PossibleValue::new("second-order"),
                Stiffening::FourthOrder => {
                    PossibleValue::new("fourth-order").aliases(["on", "true"])
                }
            })
        }
    }

    impl ValueEnum for SceneDim {
        fn value_variants<'a>() -> &'a [Self] {
            &[SceneDim::Planar, SceneDim::Spatial]
        }
        fn to_possible_value(&self) -> Option<PossibleValue> {
            Some(PossibleValue::new(match self {
                SceneDim::Planar => "planar",
                SceneDim::Spatial => "spatial",
            }))
        }
    }

    impl ValueEnum for Reference {
        fn value_variants<'a>() -> &'a [Self] {
            &[Reference::Clamped, Reference::Pinned, Reference::Free]
        }
        fn to_possible_value(&self) -> Option<PossibleValue> {
            Some(PossibleValue::new(match self {
                Reference::Clamped => "clamped",
                Reference::Pinned => "pinned",
                Reference::Free => "free",
            }))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scene_names_and_dimensions() {
        for (d, name) in SceneDim::ALL {
            assert_eq!(name.parse::<SceneDim>(), Ok(d));
            assert_eq!(d.to_string(), name);
            assert_eq!(SceneDim::from_dim(d.dim()), Some(d));
        }
        assert_eq!(SceneDim::from_dim(4), None);
        assert!("3d".parse::<SceneDim>().is_err());
    }

    #[test]
    fn frame_flags_round_trip() {
        for f in [
            FrameModel::Free,
            FrameModel::Prescribed,
            FrameModel::PrescribedAtRest,
        ] {
            let (free, zero) = f.flags();
            assert_eq!(FrameModel::from_flags(free, zero), f);
        }
        assert_eq!(FrameModel::from_flags(true, true), FrameModel::Free);
    }

    #[test]
    fn options_resolve_and_describe() {
        let o = KernelOptions::new()
            .stiffening(Stiffening::FourthOrder)
            .frame(FrameModel::PrescribedAtRest);
        assert_eq!(o.scene_or(2), SceneDim::Planar);
        assert_eq!(o.scene(SceneDim::Spatial).scene_or(2), SceneDim::Spatial);
        assert_eq!(KernelOptions::default(), KernelOptions::new());
        assert_eq!(
            o.resolved(3).describe(),
            "consistent formalism, stiffening fourth-order, spatial scene, prescribed frame motion"
        );
    }

    #[cfg(feature = "clap")]
    #[test]
    fn clap_names_match_from_str() {
        use clap::ValueEnum;
        for s in ["off", "on", "true", "false", "second-order", "fourth-order"] {
            assert_eq!(
                <Stiffening as ValueEnum>::from_str(s, false),
                s.parse::<Stiffening>(),
                "{s}"
            );
        }
        for s in ["consistent", "lumped"] {
            assert_eq!(
                <Formalism as ValueEnum>::from_str(s, false),
                s.parse::<Formalism>()
            );
        }
        for s in ["planar", "spatial"] {
            assert_eq!(
                <SceneDim as ValueEnum>::from_str(s, false),
                s.parse::<SceneDim>()
            );
        }
        for s in ["clamped", "pinned", "free"] {
            assert_eq!(
                <crate::Reference as ValueEnum>::from_str(s, false),
                s.parse::<crate::Reference>()
            );
        }
    }
}
