//! Model options of a flexible body.

use std::fmt;
use std::str::FromStr;

/// How inertia is modelled.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Formalism {
    /// Volume integrals of the shape (consistent mass).
    #[default]
    Consistent,
    /// Point masses at the nodes (half of each element's mass at each end).
    Lumped,
}

impl FromStr for Formalism {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "consistent" => Ok(Formalism::Consistent),
            "lumped" => Ok(Formalism::Lumped),
            _ => Err(format!(
                "unknown formalism `{s}`: expected consistent or lumped"
            )),
        }
    }
}

impl fmt::Display for Formalism {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Formalism::Consistent => "consistent",
            Formalism::Lumped => "lumped",
        })
    }
}

/// Geometric (centrifugal) stiffening: the strain energy beyond `½ q_fᵀ K_ff q_f`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Stiffening {
    /// Linear elasticity only.
    #[default]
    Off,
    /// von Kármán axial strain `ε̄ = ū' + ½ s̄` (element means), linear bending.
    SecondOrder,
    /// Green–Lagrange axial strain `ε̄ = ū' + ½ ū'² + ½ s̄` and the curvature
    /// of an inextensible beam to fourth order (what `on` means).
    FourthOrder,
}

impl Stiffening {
    /// Every model with its name.
    pub const ALL: [(Stiffening, &'static str); 3] = [
        (Stiffening::Off, "off"),
        (Stiffening::SecondOrder, "second-order"),
        (Stiffening::FourthOrder, "fourth-order"),
    ];

    /// Whether any stiffening energy is generated.
    pub fn is_on(self) -> bool {
        self != Stiffening::Off
    }

    /// `true` → fourth-order (the default model), `false` → off.
    pub fn from_bool(on: bool) -> Self {
        if on {
            Stiffening::FourthOrder
        } else {
            Stiffening::Off
        }
    }
}

impl FromStr for Stiffening {
    type Err = String;
    /// `off`, `on` (= `fourth-order`), `second-order`, `fourth-order`.
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "on" | "true" => Ok(Stiffening::FourthOrder),
            "off" | "false" => Ok(Stiffening::Off),
            _ => Stiffening::ALL
                .iter()
                .find(|(_, n)| *n == s)
                .map(|(m, _)| *m)
                .ok_or_else(|| {
                    format!(
                        "unknown stiffening `{s}`: expected on, off, second-order or fourth-order"
                    )
                }),
        }
    }
}

impl fmt::Display for Stiffening {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = Stiffening::ALL
            .iter()
            .find(|(m, _)| m == self)
            .map(|(_, n)| *n)
            .unwrap_or("?");
        f.write_str(name)
    }
}
