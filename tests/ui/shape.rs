// Shapes: an unknown name lists the built-in ones; a shape file that does not
// parse shows the parser's file:line:col message.

#[ffr::flex_body(shape = "beam4", elements = 2)]
pub struct Unknown { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "shapes/bad_kind.toml", elements = 2)]
pub struct BadKind { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

#[ffr::flex_body(shape = "shapes/bad_entry.toml", elements = 2)]
pub struct BadEntry { pub length: f64, pub rho: f64, pub area: f64, pub iz: f64, pub e: f64 }

fn main() {}
