// Only a struct with named fields can be a body.

#[ffr::flex_body(shape = "beam2", elements = 2)]
pub struct Tuple(pub f64, pub f64);

#[ffr::flex_body(shape = "beam2", elements = 2)]
pub enum Enum { Length(f64) }

#[ffr::flex_body(shape = "beam2", elements = 2)]
pub struct Unit;

#[ffr::flex_body(shape = "beam2", elements = 2)]
fn function() {}

fn main() { function() }
