//! Reference solutions committed with the repository (`bench/reference/`,
//! computed with an established engine; how: `bench/reference/README.md`)
//! and the error of a run against them.

use crate::benchmarks::spin_up::interpolate;

/// A reference history: times and columns.
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    /// Where it comes from (one line).
    pub source: String,
    /// Column names after `t`.
    pub columns: Vec<String>,
    /// Times (s).
    pub t: Vec<f64>,
    /// One vector per column.
    pub values: Vec<Vec<f64>>,
}

const OMEGA4: &str = include_str!("../../bench/reference/spin_up_omega4.csv");
const OMEGA10: &str = include_str!("../../bench/reference/spin_up_omega10.csv");
const PRECONE4: &str = include_str!("../../bench/reference/spin_up_precone_omega4.csv");
const GRAVITY4: &str = include_str!("../../bench/reference/spin_up_gravity_omega4.csv");

fn parse(text: &str, source: &str) -> Reference {
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .expect("a header line")
        .split(',')
        .map(str::to_string)
        .collect();
    let mut t = Vec::new();
    let mut values = vec![Vec::new(); header.len() - 1];
    for line in lines.filter(|l| !l.is_empty()) {
        let mut it = line.split(',').map(|x| x.parse::<f64>().expect("a number"));
        t.push(it.next().expect("t"));
        for v in values.iter_mut() {
            v.push(it.next().expect("a value"));
        }
    }
    Reference {
        source: source.to_string(),
        columns: header[1..].to_vec(),
        t,
        values,
    }
}

/// The geometrically exact spin-up reference at `omega` (4 or 10 rad/s).
pub fn spin_up(omega: f64) -> Option<Reference> {
    let src = "Exudyn 1.13.6 ANCF cable 2D, 64 elements, dt 1e-4 (bench/reference/README.md)";
    if omega == 4.0 {
        Some(parse(OMEGA4, src))
    } else if omega == 10.0 {
        Some(parse(OMEGA10, src))
    } else {
        None
    }
}

/// The spatial precone reference (ω_s = 4 rad/s, β = 0.05 rad).
pub fn precone() -> Reference {
    parse(
        PRECONE4,
        "Exudyn 1.13.6 ANCF cable 3D, 32 elements, dt 1e-4 (bench/reference/README.md)",
    )
}

/// The spatial spin-up under gravity along the spin axis (ω_s = 4 rad/s,
/// g = 9.81 m/s² along −z, no precone): `tip_u, tip_v, tip_w` in the hub frame.
pub fn spin_up_gravity() -> Reference {
    parse(
        GRAVITY4,
        "Exudyn 1.13.6 ANCF cable 3D, 64 elements, dt 1e-4 (bench/reference/README.md)",
    )
}

/// The most bytes a reference CSV read by [`Reference::read`] may have.
pub const MAX_REFERENCE_BYTES: u64 = 64 << 20;

impl Reference {
    /// A reference history from a CSV file: a header `t,NAME,…`, then rows
    /// of finite numbers, times strictly increasing. Errors name
    /// `file:line` (or the file) and the problem.
    pub fn read(path: &std::path::Path) -> Result<Reference, String> {
        let file = ffr::codegen::sanitize::snippet(&path.display().to_string(), usize::MAX);
        let bytes = ffr::codegen::limits::read_input(
            path,
            MAX_REFERENCE_BYTES,
            "reference CSV",
            "MAX_REFERENCE_BYTES",
        )
        .map_err(|m| format!("{file}: {m}"))?;
        let mut rd = csv::ReaderBuilder::new()
            .has_headers(true)
            .trim(csv::Trim::All)
            .from_reader(bytes.as_slice());
        let header: Vec<String> = rd
            .headers()
            .map_err(|e| format!("{file}:1: {e}"))?
            .iter()
            .map(str::to_string)
            .collect();
        if header.len() < 2 || header[0] != "t" {
            return Err(format!(
                "{file}:1: the header must be `t` and one name per column (`t,tip_transverse`)"
            ));
        }
        let mut t: Vec<f64> = Vec::new();
        let mut values = vec![Vec::new(); header.len() - 1];
        for rec in rd.records() {
            let rec = rec.map_err(|e| {
                let line = e.position().map_or(0, |p| p.line());
                format!("{file}:{line}: {e}")
            })?;
            let line = rec.position().map_or(0, |p| p.line());
            if rec.len() != header.len() {
                return Err(format!(
                    "{file}:{line}: {} fields, the header has {}",
                    rec.len(),
                    header.len()
                ));
            }
            for (i, f) in rec.iter().enumerate() {
                let x: f64 = f
                    .parse()
                    .ok()
                    .filter(|x: &f64| x.is_finite())
                    .ok_or_else(|| {
                        format!(
                            "{file}:{line}: `{}` in column `{}` is not a finite number",
                            ffr::codegen::sanitize::snippet(f, 40),
                            header[i]
                        )
                    })?;
                if i == 0 {
                    if t.last().is_some_and(|&p| !(x > p)) {
                        return Err(format!(
                            "{file}:{line}: t = {x} does not come after the previous time"
                        ));
                    }
                    t.push(x);
                } else {
                    values[i - 1].push(x);
                }
            }
        }
        if t.is_empty() {
            return Err(format!("{file}: no rows after the header"));
        }
        Ok(Reference {
            source: file,
            columns: header[1..].to_vec(),
            t,
            values,
        })
    }

    /// The column named `name`.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .position(|c| c == name)
            .map(|i| self.values[i].as_slice())
    }

    /// `max_k |y(t_k) − y_ref(t_k)| / max_k |y_ref(t_k)|` over the run's
    /// sample times `t_k ≤ t_end` (the reference interpolated linearly), and
    /// the largest absolute difference.
    pub fn error(&self, column: &str, t: &[f64], y: &[f64], t_end: f64) -> Option<(f64, f64)> {
        let r = self.column(column)?;
        let (mut diff, mut scale) = (0.0f64, 0.0f64);
        for (&tk, &yk) in t.iter().zip(y) {
            if tk > t_end + 1e-9 {
                break;
            }
            let yr = interpolate(&self.t, r, tk)?;
            diff = diff.max((yk - yr).abs());
            scale = scale.max(yr.abs());
        }
        (scale > 0.0).then(|| (diff / scale, diff))
    }

    /// `max_k |y(t_k) − y_ref(t_k)|` over the run's sample times `t_k` inside
    /// the reference's time span (the reference interpolated linearly), and
    /// the number of samples compared; `None` if no sample is inside or the
    /// column is not there.
    pub fn max_abs_difference(&self, column: &str, t: &[f64], y: &[f64]) -> Option<(f64, usize)> {
        let r = self.column(column)?;
        let (mut diff, mut n) = (0.0f64, 0);
        for (&tk, &yk) in t.iter().zip(y) {
            if let Some(yr) = interpolate(&self.t, r, tk) {
                diff = diff.max((yk - yr).abs());
                n += 1;
            }
        }
        (n > 0).then_some((diff, n))
    }

    /// The most negative value of a column and its time.
    pub fn min(&self, column: &str) -> Option<(f64, f64)> {
        let r = self.column(column)?;
        self.t
            .iter()
            .zip(r)
            .map(|(a, b)| (*a, *b))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }
}
