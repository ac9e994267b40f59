//! Reference solutions committed with the repository (`bench/reference/`,
//! computed with an established engine; how: `bench/reference/README.md`)
//! and the error of a run against them.

use crate::benchmarks::spin_up::interpolate;

/// A reference history: times and columns.
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    /// Where it comes from (one line).
    pub source: String,
    /// The names of the columns read (after `t`; all of them unless the
    /// reader was given the ones wanted).
    pub columns: Vec<String>,
    /// Every column name of the header after `t`, read or not.
    pub header: Vec<String>,
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
        header: header[1..].to_vec(),
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

/// The most numbers (times and the values of the columns read) that the
/// references one command reads may hold together: 2^24 numbers, 128 MiB
/// of `f64`. Checked after counting a file's rows, before its numbers are
/// stored; a study's references share it.
pub const MAX_REFERENCE_VALUES: usize = 1 << 24;

/// The longest line of a reference CSV, in bytes (a line is parsed whole).
pub const MAX_REFERENCE_LINE: usize = 1 << 20;

/// The most columns of a reference CSV (`t` included).
pub const MAX_REFERENCE_COLUMNS: usize = 4096;

/// A line of a reference CSV longer than [`MAX_REFERENCE_LINE`] (the error
/// inside the `io::Error` the CSV reader passes on).
#[derive(Debug)]
struct LineTooLong(u64);

impl std::fmt::Display for LineTooLong {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "line {} is longer than {MAX_REFERENCE_LINE} bytes (MAX_REFERENCE_LINE)",
            self.0
        )
    }
}

impl std::error::Error for LineTooLong {}

/// A reader that fails on a line longer than [`MAX_REFERENCE_LINE`], so
/// that no record is larger (the CSV reader holds a record whole).
struct Lines<R> {
    inner: R,
    line: u64,
    since_newline: usize,
}

impl<R: std::io::Read> std::io::Read for Lines<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        for &b in &buf[..n] {
            if b == b'\n' {
                self.line += 1;
                self.since_newline = 0;
            } else {
                self.since_newline += 1;
                if self.since_newline > MAX_REFERENCE_LINE {
                    return Err(std::io::Error::other(LineTooLong(self.line)));
                }
            }
        }
        Ok(n)
    }
}

/// A CSV reader over `f` as a reference is read (headers, fields trimmed,
/// at most [`MAX_REFERENCE_BYTES`] + 1 bytes, lines bounded).
fn reader(f: &mut std::fs::File) -> csv::Reader<Lines<std::io::Take<&mut std::fs::File>>> {
    use std::io::Read;
    csv::ReaderBuilder::new()
        .has_headers(true)
        .trim(csv::Trim::All)
        .from_reader(Lines {
            inner: f.take(MAX_REFERENCE_BYTES + 1),
            line: 1,
            since_newline: 0,
        })
}

impl Reference {
    /// A reference history from a CSV file, every column: a header
    /// `t,NAME,…`, then rows of finite numbers, times strictly increasing
    /// (see [`Reference::read_columns`]).
    pub fn read(path: &std::path::Path) -> Result<Reference, String> {
        Reference::read_columns(path, None, 0)
    }

    /// A reference history from a CSV file: a header `t,NAME,…` (names
    /// distinct), then rows of numbers, times strictly increasing and
    /// finite. Only the columns named in `wanted` that the file has are
    /// stored (every column with `None`), and only theirs are checked to
    /// be finite numbers; the others must be there (as many fields as the
    /// header), nothing more. The file is read twice, as a stream: once to
    /// count its rows, then, if the times and the columns read fit in
    /// [`MAX_REFERENCE_VALUES`] with the `already` numbers other
    /// references hold, to store them. Errors name `file:line` (or the
    /// file) and the problem.
    pub fn read_columns(
        path: &std::path::Path,
        wanted: Option<&[&str]>,
        already: usize,
    ) -> Result<Reference, String> {
        use std::io::Seek;
        let file = ffr_spec::text::path_text(&path.display().to_string());
        let at = |m: String| format!("{file}: {m}");
        let meta = std::fs::metadata(path).map_err(|e| at(e.to_string()))?;
        if meta.is_dir() {
            return Err(at("is a directory, not a reference CSV".into()));
        }
        if !meta.is_file() {
            return Err(at(format!(
                "is {}, not a regular file: a reference CSV must be a regular file (not read)",
                ffr::codegen::limits::special_kind(&meta.file_type())
            )));
        }
        let too_large = || {
            at(format!(
                "larger than {MAX_REFERENCE_BYTES} bytes, the limit for reference CSVs (MAX_REFERENCE_BYTES): not read"
            ))
        };
        if meta.len() > MAX_REFERENCE_BYTES {
            return Err(too_large());
        }
        let mut f = std::fs::File::open(path).map_err(|e| at(e.to_string()))?;
        let csv_error = |e: csv::Error| -> String {
            if let csv::ErrorKind::Io(io) = e.kind() {
                if let Some(long) = io.get_ref().and_then(|x| x.downcast_ref::<LineTooLong>()) {
                    return format!("{file}:{}: {long}", long.0);
                }
            }
            let line = e.position().map_or(0, |p| p.line());
            format!(
                "{file}:{line}: {}",
                ffr::codegen::sanitize::snippet(&e.to_string(), 200)
            )
        };
        // First pass: the header, and the rows counted.
        let mut rd = reader(&mut f);
        let header: Vec<String> = rd
            .headers()
            .map_err(csv_error)?
            .iter()
            .map(str::to_string)
            .collect();
        if header.len() < 2 || header[0] != "t" {
            return Err(format!(
                "{file}:1: the header must be `t` and one name per column (`t,tip_transverse`)"
            ));
        }
        if header.len() > MAX_REFERENCE_COLUMNS {
            return Err(format!(
                "{file}:1: {} columns, more than {MAX_REFERENCE_COLUMNS} (MAX_REFERENCE_COLUMNS)",
                header.len()
            ));
        }
        for (j, name) in header.iter().enumerate() {
            if let Some(i) = header[..j].iter().position(|h| h == name) {
                return Err(format!(
                    "{file}:1: column `{}` appears twice (columns {} and {}); name each column once",
                    ffr::codegen::sanitize::snippet(name, 64),
                    i + 1,
                    j + 1
                ));
            }
        }
        // The columns stored: their index in a row, and their names.
        let read: Vec<usize> = (1..header.len())
            .filter(|&i| wanted.is_none_or(|w| w.contains(&header[i].as_str())))
            .collect();
        let mut rec = csv::ByteRecord::new();
        let mut rows: usize = 0;
        while rd.read_byte_record(&mut rec).map_err(csv_error)? {
            let line = rec.position().map_or(0, |p| p.line());
            if rec.len() != header.len() {
                return Err(format!(
                    "{file}:{line}: {} fields, the header has {}",
                    rec.len(),
                    header.len()
                ));
            }
            rows += 1;
        }
        if rd.into_inner().inner.limit() == 0 {
            return Err(too_large());
        }
        if rows == 0 {
            return Err(at("no rows after the header".into()));
        }
        // The bound, before anything is stored.
        let per_row = 1 + read.len();
        let values = rows.saturating_mul(per_row);
        if values.saturating_add(already) > MAX_REFERENCE_VALUES {
            return Err(at(if already == 0 {
                format!(
                    "{rows} rows of t and {} column(s) read are {values} numbers, more than MAX_REFERENCE_VALUES ({MAX_REFERENCE_VALUES}); give a shorter or coarser reference",
                    read.len()
                )
            } else {
                format!(
                    "{rows} rows of t and {} column(s) read are {values} numbers; with the {already} of the other references read that is more than MAX_REFERENCE_VALUES ({MAX_REFERENCE_VALUES}) together; give shorter or coarser references, or fewer of them",
                    read.len()
                )
            }));
        }
        // Second pass: the numbers of the columns read.
        f.rewind().map_err(|e| at(e.to_string()))?;
        let mut rd = reader(&mut f);
        rd.byte_headers().map_err(csv_error)?;
        let mut t: Vec<f64> = Vec::with_capacity(rows);
        let mut cols: Vec<Vec<f64>> = read.iter().map(|_| Vec::with_capacity(rows)).collect();
        let number = |f: &[u8], i: usize, line: u64| -> Result<f64, String> {
            std::str::from_utf8(f)
                .ok()
                .and_then(|s| s.parse::<f64>().ok())
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    format!(
                        "{file}:{line}: `{}` in column `{}` is not a finite number",
                        ffr::codegen::sanitize::snippet(&String::from_utf8_lossy(f), 40),
                        ffr::codegen::sanitize::snippet(&header[i], 64)
                    )
                })
        };
        while rd.read_byte_record(&mut rec).map_err(csv_error)? {
            let line = rec.position().map_or(0, |p| p.line());
            if t.len() == rows || rec.len() != header.len() {
                return Err(at("changed while it was read".into()));
            }
            let x = number(&rec[0], 0, line)?;
            if t.last().is_some_and(|&p| !(x > p)) {
                return Err(format!(
                    "{file}:{line}: t = {} does not come after the previous time",
                    crate::output::number(x)
                ));
            }
            t.push(x);
            for (c, &i) in cols.iter_mut().zip(&read) {
                c.push(number(&rec[i], i, line)?);
            }
        }
        if t.len() != rows {
            return Err(at("changed while it was read".into()));
        }
        Ok(Reference {
            source: file,
            columns: read.iter().map(|&i| header[i].clone()).collect(),
            header: header[1..].to_vec(),
            t,
            values: cols,
        })
    }

    /// The numbers this reference holds (times and the columns read).
    pub fn numbers(&self) -> usize {
        self.t.len() * (1 + self.values.len())
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
    /// the largest absolute difference; `None` when a time is outside the
    /// reference. The relative error of a reference that is zero throughout
    /// is `None` ([`Reference::abs_error`] still has the absolute one).
    pub fn error(&self, column: &str, t: &[f64], y: &[f64], t_end: f64) -> Option<(f64, f64)> {
        let (rel, abs) = self.abs_error(column, t, y, t_end)?;
        Some((rel?, abs))
    }

    /// [`Reference::error`] with the relative error `None` for a reference
    /// that is zero throughout, where only the absolute error is defined.
    pub fn abs_error(
        &self,
        column: &str,
        t: &[f64],
        y: &[f64],
        t_end: f64,
    ) -> Option<(Option<f64>, f64)> {
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
        Some(((scale > 0.0).then(|| diff / scale), diff))
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

#[cfg(test)]
mod tests {
    use super::Reference;

    /// A reference column that is zero throughout has an absolute error
    /// and no relative one (the absolute error failed with it before).
    #[test]
    fn a_zero_reference_has_an_absolute_error_only() {
        let r = Reference {
            source: "test".into(),
            columns: vec!["zero".into(), "ramp".into()],
            header: vec!["zero".into(), "ramp".into()],
            t: vec![0.0, 1.0, 2.0],
            values: vec![vec![0.0; 3], vec![0.0, 1.0, 2.0]],
        };
        let (t, y) = ([0.0, 0.5, 1.0], [0.0, 0.25, -0.5]);
        assert_eq!(r.abs_error("zero", &t, &y, 1.0), Some((None, 0.5)));
        assert_eq!(r.error("zero", &t, &y, 1.0), None);
        // 0.5 − 0.25 at t = 0.5 and 1 − (−0.5) at t = 1, over max |ramp| = 1.
        assert_eq!(r.error("ramp", &t, &y, 1.0), Some((1.5, 1.5)));
        assert_eq!(r.abs_error("ramp", &[5.0], &[0.0], 5.0), None, "outside");
    }
}
