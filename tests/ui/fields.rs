// Parameter fields: the ones the shape uses must exist and be `f64`
// (a planar beam2 uses length, rho, area, iz, e; other fields are fine).

#[ffr::flex_body(shape = "beam2", elements = 2)]
pub struct MissingFields { pub length: f64, pub rho: f64, pub name: String }

#[ffr::flex_body(shape = "beam2", elements = 2)]
pub struct WrongTypes { pub length: f32, pub rho: f64, pub area: f64, pub iz: Vec<f64>, pub e: f64, pub j: u8 }

fn main() {}
