// Misused options: each error points at the offending token and says what is allowed.

#[ffr::flex_body(shape = "beam2", elements = 2, shap = "beam3")]
pub struct UnknownOption { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam2", elements = 0)]
pub struct ZeroElements { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam2", elements = "8")]
pub struct StringElements { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam2", elements = 2.5)]
pub struct FloatElements { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam2", elements = 300)]
pub struct TooManyElements { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam2", elements = 2, reference = "hinged", formalism = "exact")]
pub struct BadNames { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = beam2, elements = 2, stiffening = "yes")]
pub struct NotLiterals { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam2", elements = 2, elements = 3)]
pub struct Twice { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(reference = "clamped")]
pub struct Missing { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam3", elements = 2, scene = "planar")]
pub struct Flat { pub length: f64, pub rho: f64, pub area: f64, pub iy: f64, pub iz: f64, pub e: f64, pub g: f64, pub j: f64 }

#[ffr::flex_body(shape = "beam2", elements = 2, scene = "lunar", stiffening = "third-order")]
pub struct Lunar { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam2", elements = 2, sections = "shapes/no_such_table.csv")]
pub struct NoTable {}

#[ffr::flex_body(shape = "beam2", elements = 2, sections = "shapes/bad_table.csv")]
pub struct BadTable {}

fn main() {}

#[ffr::flex_body(shape = "beam2", elements = 2, modes = 2)]
pub struct ModesWithoutParams { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam2", elements = 2, static_modes = true, boundary_nodes = [2])]
pub struct ModalOptionsWithoutModes { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam2", elements = 2, modes = 0, reduction = "guyan", params(length = 1.0, rh = 2.0, e = "7e10"))]
pub struct BadModalValues { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam2", elements = 2, modes = 1, boundary_nodes = [2], modal_damping = "0.02", params(length = 1.0))]
pub struct BoundaryWithoutCraigBampton { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam2", elements = 2, modes = 9, params(length = 1.0, rho = 2700.0))]
pub struct ModalParamsMissing { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam2", elements = 2, modes = 9, params(length = 1.0, rho = 2700.0, area = 1e-4, iz = 1e-9, e = 7e10))]
pub struct TooManyModes { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }
