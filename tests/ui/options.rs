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
