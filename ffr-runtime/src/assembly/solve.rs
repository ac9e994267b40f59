//! Factoring and solving the bordered system, and naming the unknown at
//! which a factorization fails.

use super::{Assembly, Slot};
use crate::body::Body;
use crate::error::{Error, Result};

impl<B: Body> Assembly<'_, B> {
    /// Factor the matrix in the solver.
    pub fn factor(&mut self, t: f64, what: &'static str) -> Result<()> {
        match self.solver.factor() {
            Ok(()) => Ok(()),
            Err(e) => Err(Error::Singular {
                what,
                t,
                detail: self.describe_singular(&e),
            }),
        }
    }

    /// The solver's failure with the unknown it stopped at named (the body
    /// and coordinate, or the constraint row), so that the message says
    /// which coordinate has no inertia or which joint is redundant.
    pub(super) fn describe_singular(&self, e: &crate::linalg::Singular) -> String {
        use crate::linalg::Part;
        let slot = match e.part {
            Part::Block(b) => Slot::Band(b as u32, e.column as u32),
            Part::Schur => Slot::Border(e.column as u32),
            Part::Matrix => return e.to_string(),
        };
        match self.describe_slot(slot) {
            Some(what) => format!("{e}: {what}"),
            None => e.to_string(),
        }
    }

    /// The unknown in `slot`: ``coordinate `θ` of body `bar` (…)``, the
    /// Euler-parameter normalization of a body, or a row of a joint.
    pub(super) fn describe_slot(&self, slot: Slot) -> Option<String> {
        if let Some(c) = self.coord_slot.iter().position(|s| *s == slot) {
            let b = self
                .sys
                .bodies
                .iter()
                .find(|b| (b.offset..b.offset + b.n_coords()).contains(&c))?;
            let k = c - b.offset;
            let name = if k < b.d {
                ["R_x", "R_y", "R_z"][k].to_string()
            } else if k < b.d + b.n_theta {
                if b.n_theta == 1 {
                    "θ".to_string()
                } else {
                    format!("e{}", k - b.d)
                }
            } else {
                b.body
                    .layout()
                    .labels
                    .get(k - b.d - b.n_theta)
                    .cloned()
                    .unwrap_or_else(|| format!("q_f[{}]", k - b.d - b.n_theta))
            };
            return Some(format!(
                "coordinate `{name}` of body `{}` ({})",
                b.name,
                b.body.layout().description
            ));
        }
        if let Slot::Border(g) = slot {
            if let Some(k) = self.mult_slot.iter().position(|s| *s == g) {
                if let Some(&(i, _)) = self.norm_rows.iter().find(|(_, row)| *row == k) {
                    return Some(format!(
                        "the Euler-parameter normalization of body `{}`",
                        self.sys.bodies[i].name
                    ));
                }
                for (c, cw) in self.sys.constraints.iter().zip(&self.cons) {
                    if (cw.first..cw.first + c.rows.len()).contains(&k) {
                        return Some(format!("row {} of a {} joint", k - cw.first, c.kind));
                    }
                }
            }
        }
        None
    }

    /// Solve `J x = rhs` with the factored matrix: `rhs` in coordinate/row
    /// space (`n + m`), `x` likewise (prescribed coordinates get 0).
    pub fn solve(&mut self, rhs: &[f64], x: &mut [f64]) {
        let n = self.n;
        for (c, s) in self.coord_slot.iter().enumerate() {
            match *s {
                Slot::Band(b, i) => {
                    let r = self.solver.block_range(b as usize);
                    self.x_band[r.start + i as usize] = rhs[c];
                }
                Slot::Border(g) => self.x_border[g as usize] = rhs[c],
                Slot::Fixed => {}
            }
        }
        for (k, &g) in self.mult_slot.iter().enumerate() {
            self.x_border[g as usize] = rhs[n + k];
        }
        self.solver.solve(&mut self.x_band, &mut self.x_border);
        for (c, s) in self.coord_slot.iter().enumerate() {
            x[c] = match *s {
                Slot::Band(b, i) => {
                    let r = self.solver.block_range(b as usize);
                    self.x_band[r.start + i as usize]
                }
                Slot::Border(g) => self.x_border[g as usize],
                Slot::Fixed => 0.0,
            };
        }
        for (k, &g) in self.mult_slot.iter().enumerate() {
            x[n + k] = self.x_border[g as usize];
        }
    }
}
