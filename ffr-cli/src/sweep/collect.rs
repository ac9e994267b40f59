//! The figures a study collects from each run: an output's extreme or final
//! value, or its error against a reference CSV (the error `ffr report` uses,
//! [`Reference::error`]).

use crate::reference::Reference;
use ffr::scene::SceneRun;
use std::sync::Arc;

/// A statistic of one output over a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stat {
    /// The smallest value.
    Min,
    /// The largest value.
    Max,
    /// The largest magnitude.
    AbsMax,
    /// The value at the end of the run.
    Final,
    /// `max_k |y(t_k) − y_ref(t_k)| / max_k |y_ref(t_k)|` over the run's
    /// sample times, the reference interpolated linearly (as `ffr report`).
    MaxError,
    /// `max_k |y(t_k) − y_ref(t_k)|`.
    MaxAbsError,
}

impl Stat {
    /// The names a study file uses.
    pub const NAMES: [&'static str; 6] = [
        "min",
        "max",
        "absmax",
        "final",
        "max_error",
        "max_abs_error",
    ];

    /// The statistic called `name`.
    pub fn from_name(name: &str) -> Option<Stat> {
        Some(match name {
            "min" => Stat::Min,
            "max" => Stat::Max,
            "absmax" => Stat::AbsMax,
            "final" => Stat::Final,
            "max_error" => Stat::MaxError,
            "max_abs_error" => Stat::MaxAbsError,
            _ => return None,
        })
    }

    /// Its name in a study file.
    pub fn name(self) -> &'static str {
        match self {
            Stat::Min => "min",
            Stat::Max => "max",
            Stat::AbsMax => "absmax",
            Stat::Final => "final",
            Stat::MaxError => "max_error",
            Stat::MaxAbsError => "max_abs_error",
        }
    }

    /// Whether it compares with a reference.
    pub fn needs_reference(self) -> bool {
        matches!(self, Stat::MaxError | Stat::MaxAbsError)
    }
}

/// A figure: a column of `results.csv`.
#[derive(Clone, Debug)]
pub struct Figure {
    /// Its column name.
    pub name: String,
    /// The scene output it reads.
    pub output: String,
    /// The statistic.
    pub stat: Stat,
    /// The reference and its column (error statistics).
    pub reference: Option<(Arc<Reference>, String)>,
}

impl Figure {
    /// The figure of a complete run whose every value is finite, or why
    /// there is none.
    pub fn of(&self, run: &SceneRun) -> Result<f64, String> {
        let i = run
            .names
            .iter()
            .position(|n| n == &self.output)
            .ok_or_else(|| format!("the scene has no output `{}`", self.output))?;
        let y = &run.columns[i];
        let (Some(&first), Some(&last)) = (y.first(), y.last()) else {
            return Err(format!("output `{}` recorded no value", self.output));
        };
        let v = match self.stat {
            Stat::Min => y.iter().copied().fold(first, f64::min),
            Stat::Max => y.iter().copied().fold(first, f64::max),
            Stat::AbsMax => y.iter().map(|v| v.abs()).fold(0.0, f64::max),
            Stat::Final => last,
            Stat::MaxError | Stat::MaxAbsError => {
                let (r, column) = self.reference.as_ref().ok_or("no reference")?;
                let t_end = run.t.last().copied().unwrap_or(0.0);
                let (rel, abs) = r.abs_error(column, &run.t, y, t_end).ok_or_else(|| {
                    format!(
                        "the run's times (0 to {} s) are outside the reference's",
                        ffr::runtime::spec::text::Num(t_end)
                    )
                })?;
                if self.stat == Stat::MaxError {
                    rel.ok_or_else(|| {
                        format!(
                            "the reference's column `{}` is zero throughout: its relative error is not defined (use max_abs_error)",
                            ffr::runtime::spec::text::quoted(column)
                        )
                    })?
                } else {
                    abs
                }
            }
        };
        if !v.is_finite() {
            return Err(format!(
                "figure `{}` is {v}, not a finite number",
                self.name
            ));
        }
        Ok(v)
    }
}
