//! The parameters of a beam body (SI units), as generated code and the
//! command line name them.

use std::fmt;

/// A body parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Param {
    /// Element length `l = L / N` (derived; element kernels are written in it).
    ElemLength,
    /// Body length `L` (m).
    Length,
    /// Density `ρ` (kg/m³).
    Rho,
    /// Cross-section area `A` (m²).
    Area,
    /// `I_y = ∫z² dA` (m⁴).
    Iy,
    /// `I_z = ∫y² dA` (m⁴).
    Iz,
    /// Young's modulus `E` (Pa).
    E,
    /// Shear modulus `G` (Pa).
    G,
    /// Torsion constant `J` (m⁴).
    J,
}

impl Param {
    /// Every runtime field of a body, in declaration order (not the derived `l`).
    pub const FIELDS: [Param; 8] = [
        Param::Length,
        Param::Rho,
        Param::Area,
        Param::Iy,
        Param::Iz,
        Param::E,
        Param::G,
        Param::J,
    ];

    /// The field name in generated code, scene files and on the command line.
    pub fn field(self) -> &'static str {
        match self {
            Param::ElemLength => "l",
            Param::Length => "length",
            Param::Rho => "rho",
            Param::Area => "area",
            Param::Iy => "iy",
            Param::Iz => "iz",
            Param::E => "e",
            Param::G => "g",
            Param::J => "j",
        }
    }

    /// Index into [`Param::FIELDS`] (`None` for the element length).
    pub fn field_index(self) -> Option<usize> {
        Param::FIELDS.iter().position(|&p| p == self)
    }

    /// A one-line description with the unit.
    pub fn doc(self) -> &'static str {
        match self {
            Param::ElemLength => "Element length `l = L / N` (m)",
            Param::Length => "Body length `L` (m)",
            Param::Rho => "Density `ρ` (kg/m³)",
            Param::Area => "Cross-section area `A` (m²)",
            Param::Iy => "Second moment `I_y = ∫z² dA` (m⁴)",
            Param::Iz => "Second moment `I_z = ∫y² dA` (m⁴)",
            Param::E => "Young's modulus `E` (Pa)",
            Param::G => "Shear modulus `G` (Pa)",
            Param::J => "Torsion constant `J` (m⁴)",
        }
    }

    /// Whether the parameter must be strictly positive (else only ≥ 0).
    pub fn must_be_positive(self) -> bool {
        matches!(
            self,
            Param::ElemLength | Param::Length | Param::Rho | Param::Area | Param::E
        )
    }
}

/// Values of a body's parameters (SI units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// Body length `L` (m); elements have `l = L / N`.
    pub length: f64,
    /// Density `ρ` (kg/m³).
    pub rho: f64,
    /// Cross-section area `A` (m²).
    pub area: f64,
    /// Second moment `I_y = ∫z² dA` (m⁴).
    pub iy: f64,
    /// Second moment `I_z = ∫y² dA` (m⁴).
    pub iz: f64,
    /// Young's modulus `E` (Pa).
    pub e: f64,
    /// Shear modulus `G` (Pa).
    pub g: f64,
    /// Torsion constant `J` (m⁴).
    pub j: f64,
}

impl Params {
    /// The command line's defaults (`ffr invariants`, `modes`, `export`
    /// and the Python package's): a 1 m steel bar of 10 mm × 10 mm square
    /// section.
    pub const STEEL_BAR: Params = Params {
        length: 1.0,
        rho: 7850.0,
        area: 1e-4,
        iy: 1e-8 / 12.0,
        iz: 1e-8 / 12.0,
        e: 2.1e11,
        g: 8.1e10,
        j: 1.406e-8,
    };
}

/// A parameter value that is not physically valid.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamError {
    /// Which parameter.
    pub param: Param,
    /// Its value.
    pub value: f64,
}

impl ParamError {
    /// What is wrong with the value, e.g. `must be positive, found -1`.
    pub fn reason(&self) -> String {
        let v = self.value;
        if !v.is_finite() {
            format!("must be finite, found {v}")
        } else if v > 0.0 && !v.is_normal() {
            format!(
                "is subnormal, found {}: below {:e}, the smallest normal f64, products with it underflow to 0",
                crate::text::Num(v),
                f64::MIN_POSITIVE
            )
        } else if v < 0.0 {
            if self.param.must_be_positive() {
                format!("must be positive, found {v}")
            } else {
                format!("must not be negative, found {v}")
            }
        } else if self.param.must_be_positive() {
            format!("must be positive, found {v}")
        } else {
            format!("must be positive for this body, which uses it, found {v}")
        }
    }
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "parameter `{}` {} ({})",
            self.param.field(),
            self.reason(),
            self.param.doc()
        )
    }
}

impl std::error::Error for ParamError {}

impl Params {
    /// In [`Param::FIELDS`] order.
    pub fn to_array(&self) -> [f64; 8] {
        [
            self.length,
            self.rho,
            self.area,
            self.iy,
            self.iz,
            self.e,
            self.g,
            self.j,
        ]
    }

    /// From values in [`Param::FIELDS`] order.
    pub fn from_array(v: [f64; 8]) -> Self {
        Self {
            length: v[0],
            rho: v[1],
            area: v[2],
            iy: v[3],
            iz: v[4],
            e: v[5],
            g: v[6],
            j: v[7],
        }
    }

    /// The value of `p` (`l` is not a field: use [`Params::elem_length`]).
    pub fn get(&self, p: Param) -> Option<f64> {
        p.field_index().map(|i| self.to_array()[i])
    }

    /// `name = value` for the parameters in `used` (messages).
    pub fn describe(&self, used: &[Param]) -> String {
        Param::FIELDS
            .iter()
            .zip(self.to_array())
            .filter(|(p, _)| used.contains(p))
            .map(|(p, v)| format!("{} = {v:e}", p.field()))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// `l = L / N`.
    pub fn elem_length(&self, elements: usize) -> f64 {
        self.length / elements as f64
    }

    /// Every value finite; `length, rho, area, e` strictly positive;
    /// `iy, iz, g, j` not negative.
    pub fn validate(&self) -> Result<(), ParamError> {
        for (p, v) in Param::FIELDS.iter().zip(self.to_array()) {
            let ok = v.is_finite()
                && if p.must_be_positive() {
                    v.is_normal() && v > 0.0
                } else {
                    v == 0.0 || (v.is_normal() && v > 0.0)
                };
            if !ok {
                return Err(ParamError {
                    param: *p,
                    value: v,
                });
            }
        }
        Ok(())
    }

    /// The parameters in `used` finite and strictly positive (a section
    /// constant a body uses and that is 0 leaves a direction without
    /// stiffness or inertia); a shape that does not read a parameter accepts
    /// any value, 0 included.
    pub fn validate_only(&self, used: &[Param]) -> Result<(), ParamError> {
        for (p, v) in Param::FIELDS.iter().zip(self.to_array()) {
            if used.contains(p) && !(v.is_normal() && v > 0.0) {
                return Err(ParamError {
                    param: *p,
                    value: v,
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subnormal_values_are_refused_by_name() {
        let p = Params::STEEL_BAR;
        for bad in [Params { rho: 1e-310, ..p }, Params { iy: 1e-315, ..p }] {
            let e = bad.validate().unwrap_err();
            assert!(e.reason().starts_with("is subnormal, found 1e-3"), "{e}");
            assert!(bad.validate_only(&[e.param]).is_err());
        }
        assert!(p.validate().is_ok());
    }

    #[test]
    fn validation_names_the_parameter() {
        let p = Params::from_array([1.0, 7850.0, 1e-4, 0.0, 8e-10, 2.1e11, 0.0, 0.0]);
        assert!(p.validate().is_ok());
        let bad = Params { area: -1e-4, ..p };
        assert!(bad
            .validate()
            .unwrap_err()
            .to_string()
            .starts_with("parameter `area`"));
        let bad = Params { iz: -1.0, ..p };
        assert!(bad
            .validate()
            .unwrap_err()
            .to_string()
            .contains("`iz` must not be negative, found -1"));
        let bad = Params { e: f64::NAN, ..p };
        assert!(bad
            .validate()
            .unwrap_err()
            .to_string()
            .contains("`e` must be finite"));
        // A parameter the body uses must be positive; others may be 0 or anything.
        let used = [Param::Length, Param::Rho, Param::Area, Param::Iz, Param::E];
        assert!(p.validate_only(&used).is_ok());
        let e = p.validate_only(&[Param::Iy]).unwrap_err();
        assert_eq!(e.param, Param::Iy);
        assert!(e
            .to_string()
            .contains("must be positive for this body, which uses it, found 0"));
        let odd = Params {
            j: f64::NAN,
            g: -1.0,
            ..p
        };
        assert!(odd.validate_only(&used).is_ok());
        assert_eq!(Params::from_array(p.to_array()), p);
    }
}
