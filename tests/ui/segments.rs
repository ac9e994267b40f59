// `segments = N` on the attribute: each error points at the value and says what is allowed.

#[ffr::flex_body(shape = "beam2", elements = 8, segments = 0)]
pub struct ZeroSegments { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam2", elements = 8, segments = 3)]
pub struct NotADivisor { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam2", elements = 4, segments = 8)]
pub struct MoreThanElements { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam2", elements = 8, segments = 2.0)]
pub struct FloatSegments { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam2", elements = 8, segments = -2)]
pub struct NegativeSegments { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "beam2", elements = 8, segments = 2, modes = 2, params(length = 1.0, rho = 2700.0, area = 1e-4, iz = 1e-9, e = 7e10))]
pub struct ModalSegments { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

fn main() {}
