//! The bordered block-banded system: banded blocks coupled through a dense
//! border, solved by block elimination (Schur complement on the border).

use std::ops::Range;

use super::{BandMatrix, DenseLu, Part, PivotInfo, Singular};

/// The border matrix `D` and then its Schur complement `S`: dense, or
/// banded when the border's order makes it so ([`BorderedSystem::with_banded_border`]).
#[derive(Debug, Clone)]
enum Schur {
    Dense(DenseLu),
    Band(BandMatrix),
}

impl Schur {
    fn clear(&mut self) {
        match self {
            Schur::Dense(d) => d.clear(),
            Schur::Band(b) => b.clear(),
        }
    }
    #[inline]
    fn add(&mut self, i: usize, j: usize, v: f64) {
        match self {
            Schur::Dense(d) => d.add(i, j, v),
            Schur::Band(b) => b.add(i, j, v),
        }
    }
    fn factor(&mut self) -> Result<(), Singular> {
        match self {
            Schur::Dense(d) => d.factor(),
            Schur::Band(b) => b.factor(),
        }
    }
    fn solve(&self, x: &mut [f64]) {
        match self {
            Schur::Dense(d) => d.solve(x),
            Schur::Band(b) => b.solve(x),
        }
    }
    fn mul_vec_add(&self, x: &[f64], y: &mut [f64]) {
        match self {
            Schur::Dense(d) => d.mul_vec_add(x, y),
            Schur::Band(b) => b.mul_vec_add(x, y),
        }
    }
    fn pivot_info(&self) -> PivotInfo {
        match self {
            Schur::Dense(d) => d.pivot_info(),
            Schur::Band(b) => b.pivot_info(),
        }
    }
    fn det_sign(&self) -> f64 {
        match self {
            Schur::Dense(d) => d.det_sign(),
            Schur::Band(b) => b.det_sign(),
        }
    }
    fn get(&self, i: usize, j: usize) -> f64 {
        match self {
            Schur::Dense(d) => d.get(i, j),
            Schur::Band(b) => b.get(i, j),
        }
    }
}

/// Shape of one band block `B_i` and its coupling to the border.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BlockShape {
    /// Order `n_i` of `B_i`.
    pub n: usize,
    /// Subdiagonals `kl_i` of `B_i`.
    pub kl: usize,
    /// Superdiagonals `ku_i` of `B_i`.
    pub ku: usize,
    /// The border unknowns `border_i ⊂ 0..k` the block couples to, strictly
    /// increasing (length `m_i`): `C_i` has a column and `E_i` a row for each.
    pub border: Vec<usize>,
}

/// A mutable view of a small dense matrix in a [`BorderedSystem`]: entry
/// `(r, c)` at `r · row_stride + c · col_stride` of the underlying slice.
#[derive(Debug)]
pub struct MatMut<'a> {
    data: &'a mut [f64],
    nrows: usize,
    ncols: usize,
    row_stride: usize,
    col_stride: usize,
}

impl<'a> MatMut<'a> {
    fn new(
        data: &'a mut [f64],
        nrows: usize,
        ncols: usize,
        row_stride: usize,
        col_stride: usize,
    ) -> Self {
        debug_assert_eq!(data.len(), nrows * ncols);
        MatMut {
            data,
            nrows,
            ncols,
            row_stride,
            col_stride,
        }
    }

    /// Number of rows.
    pub fn nrows(&self) -> usize {
        self.nrows
    }

    /// Number of columns.
    pub fn ncols(&self) -> usize {
        self.ncols
    }

    /// Distance in the slice between `(r, c)` and `(r + 1, c)`.
    pub fn row_stride(&self) -> usize {
        self.row_stride
    }

    /// Distance in the slice between `(r, c)` and `(r, c + 1)`.
    pub fn col_stride(&self) -> usize {
        self.col_stride
    }

    #[inline]
    fn idx(&self, r: usize, c: usize) -> usize {
        debug_assert!(r < self.nrows && c < self.ncols, "({r}, {c}) out of range");
        r * self.row_stride + c * self.col_stride
    }

    /// Entry `(r, c)`.
    #[inline]
    pub fn get(&self, r: usize, c: usize) -> f64 {
        self.data[self.idx(r, c)]
    }

    /// `(r, c) ← v`.
    #[inline]
    pub fn set(&mut self, r: usize, c: usize, v: f64) {
        let k = self.idx(r, c);
        self.data[k] = v;
    }

    /// `(r, c) ← (r, c) + v`.
    #[inline]
    pub fn add(&mut self, r: usize, c: usize, v: f64) {
        let k = self.idx(r, c);
        self.data[k] += v;
    }

    /// Set every entry to `v`.
    pub fn fill(&mut self, v: f64) {
        self.data.fill(v);
    }

    /// The underlying slice (layout: see [`row_stride`](Self::row_stride),
    /// [`col_stride`](Self::col_stride)).
    pub fn into_slice(self) -> &'a mut [f64] {
        self.data
    }
}

/// The worst pivot statistics over all factors of a [`BorderedSystem`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PivotReport {
    /// Smallest [`PivotInfo::pivot_ratio`] (`min |u_jj| / max |a_ij|`) over
    /// the band blocks and the Schur complement (`1` if there is none).
    pub min_ratio: f64,
    /// Where it is.
    pub min_ratio_part: Part,
    /// Largest [`PivotInfo::growth`] (`max |u_ij| / max |a_ij|`).
    pub max_growth: f64,
    /// Where it is.
    pub max_growth_part: Part,
}

#[derive(Debug, Clone)]
struct Block {
    band: BandMatrix,
    border: Vec<usize>,
    offset: usize,
    /// `C_i`, `n_i × m_i` column-major; `W_i = B_i⁻¹ C_i` after factoring.
    c: Vec<f64>,
    /// `E_i`, `m_i × n_i` row-major.
    e: Vec<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum State {
    Assembling,
    Factored,
    Failed,
}

/// The bordered block-banded matrix
///
/// ```text
///     [ B_1                 C_1 P_1 ]
/// A = [       ...             ...   ]
///     [             B_N     C_N P_N ]
///     [ P_1ᵀE_1 ... P_NᵀE_N    D    ]
/// ```
///
/// (see the [module docs](super)) with its block-elimination factorization:
/// `B_i = Π_i L_i U_i`, `W_i = B_i⁻¹ C_i`,
/// `S = D − Σ_i P_iᵀ E_i W_i P_i = Π_S L_S U_S`.
///
/// Unknowns are ordered as one concatenated band vector
/// `x_band = (x_1, …, x_N)` (block `i` at [`block_range(i)`](Self::block_range))
/// and the border vector `x_border` (length `k`).
///
/// Life cycle: [`new`](Self::new) (allocates everything), then repeatedly
/// [`clear`](Self::clear); fill [`band_mut`](Self::band_mut),
/// [`c_mut`](Self::c_mut), [`e_mut`](Self::e_mut), [`d_mut`](Self::d_mut);
/// optionally [`mul_vec`](Self::mul_vec); [`factor`](Self::factor); any
/// number of [`solve`](Self::solve)s. Factoring overwrites `B_i`, `C_i` and
/// `D` with the factors (`E_i` is kept), so products with `A` must be taken
/// before. None of these calls allocates.
#[derive(Debug, Clone)]
pub struct BorderedSystem {
    blocks: Vec<Block>,
    k: usize,
    n_band: usize,
    /// `D` before factoring, then `S` and its factors.
    schur: Schur,
    state: State,
}

impl BorderedSystem {
    /// A zero matrix of the given block shapes and `k` border unknowns.
    /// Allocates all storage, including the workspace of factor and solve.
    ///
    /// Panics if a border list is not strictly increasing or has an index
    /// `≥ k`.
    pub fn new(blocks: &[BlockShape], k: usize) -> Self {
        Self::build(blocks, k, Schur::Dense(DenseLu::new(k)))
    }

    /// [`new`](Self::new) with the border matrix `D` and its Schur
    /// complement `S` in band storage (`kl` sub-, `ku` superdiagonals):
    /// for borders whose coupling is banded in their order (a chain of
    /// bodies), so that factoring `S` costs `O(k kl (kl + ku))` instead of
    /// `O(k³)`. Every entry of `D` and every coupling of a block's border
    /// unknowns (`border_i[a]`, `border_i[b]`) must lie in the band.
    ///
    /// Panics like [`new`](Self::new), and if a block's border spans more
    /// than the band.
    pub fn with_banded_border(blocks: &[BlockShape], k: usize, kl: usize, ku: usize) -> Self {
        for (i, s) in blocks.iter().enumerate() {
            if let (Some(&lo), Some(&hi)) = (s.border.first(), s.border.last()) {
                assert!(
                    hi - lo <= kl.min(ku),
                    "border of block {i} spans {} unknowns, more than the band ({kl}, {ku})",
                    hi - lo
                );
            }
        }
        Self::build(blocks, k, Schur::Band(BandMatrix::new(k, kl, ku)))
    }

    /// Whether `other` has the same block shapes, border and storage (so
    /// that one's factorization can stand in for the other's).
    pub fn same_shape(&self, other: &Self) -> bool {
        let schur = match (&self.schur, &other.schur) {
            (Schur::Dense(a), Schur::Dense(b)) => a.n() == b.n(),
            (Schur::Band(a), Schur::Band(b)) => (a.n(), a.kl(), a.ku()) == (b.n(), b.kl(), b.ku()),
            _ => false,
        };
        schur
            && self.k == other.k
            && self.n_band == other.n_band
            && self.blocks.len() == other.blocks.len()
            && self.blocks.iter().zip(&other.blocks).all(|(a, b)| {
                (a.band.n(), a.band.kl(), a.band.ku()) == (b.band.n(), b.band.kl(), b.band.ku())
                    && a.border == b.border
                    && a.offset == b.offset
            })
    }

    fn build(blocks: &[BlockShape], k: usize, schur: Schur) -> Self {
        let mut offset = 0;
        let blocks = blocks
            .iter()
            .enumerate()
            .map(|(i, s)| {
                assert!(
                    s.border.windows(2).all(|w| w[0] < w[1]),
                    "border of block {i} is not strictly increasing"
                );
                assert!(
                    s.border.iter().all(|&g| g < k),
                    "border of block {i} has an index ≥ k = {k}"
                );
                let m = s.border.len();
                let b = Block {
                    band: BandMatrix::new(s.n, s.kl, s.ku),
                    border: s.border.clone(),
                    offset,
                    c: vec![0.0; s.n * m],
                    e: vec![0.0; m * s.n],
                };
                offset += s.n;
                b
            })
            .collect();
        BorderedSystem {
            blocks,
            k,
            n_band: offset,
            schur,
            state: State::Assembling,
        }
    }

    /// Number of band blocks `N`.
    pub fn n_blocks(&self) -> usize {
        self.blocks.len()
    }

    /// Number of border unknowns `k`.
    pub fn k(&self) -> usize {
        self.k
    }

    /// Total band unknowns `Σ_i n_i` (length of `x_band`).
    pub fn n_band(&self) -> usize {
        self.n_band
    }

    /// Order of `A`: `Σ_i n_i + k`.
    pub fn dim(&self) -> usize {
        self.n_band + self.k
    }

    /// Where block `i` is in `x_band`: `o_i..o_i + n_i`, `o_i = Σ_{j<i} n_j`.
    pub fn block_range(&self, i: usize) -> Range<usize> {
        let b = &self.blocks[i];
        b.offset..b.offset + b.band.n()
    }

    /// The border indices `border_i` of block `i`.
    pub fn border(&self, i: usize) -> &[usize] {
        &self.blocks[i].border
    }

    /// The local index `l` with `border_i[l] = g`, if block `i` couples to
    /// border unknown `g` (binary search, `O(log m_i)`).
    pub fn border_local(&self, i: usize, g: usize) -> Option<usize> {
        self.blocks[i].border.binary_search(&g).ok()
    }

    /// `A ← 0` and forget the factorization. No allocation.
    pub fn clear(&mut self) {
        for b in &mut self.blocks {
            b.band.clear();
            b.c.fill(0.0);
            b.e.fill(0.0);
        }
        self.schur.clear();
        self.state = State::Assembling;
    }

    /// `B_i` (fill with [`BandMatrix::add`] in block-local indices).
    pub fn band_mut(&mut self, i: usize) -> &mut BandMatrix {
        debug_assert_eq!(self.state, State::Assembling, "band_mut after factor");
        &mut self.blocks[i].band
    }

    /// `B_i` (or its factors).
    pub fn band(&self, i: usize) -> &BandMatrix {
        &self.blocks[i].band
    }

    /// `C_i` (`n_i × m_i`): row = block-local unknown, column `l` = border
    /// unknown `border_i[l]`. Stored column-major (`row_stride 1`,
    /// `col_stride n_i`), so each column is one contiguous slice.
    pub fn c_mut(&mut self, i: usize) -> MatMut<'_> {
        debug_assert_eq!(self.state, State::Assembling, "c_mut after factor");
        let b = &mut self.blocks[i];
        let (n, m) = (b.band.n(), b.border.len());
        MatMut::new(&mut b.c, n, m, 1, n)
    }

    /// Column `l` of `C_i` (length `n_i`): the coupling of block `i` to
    /// border unknown `border_i[l]`.
    pub fn c_col_mut(&mut self, i: usize, l: usize) -> &mut [f64] {
        debug_assert_eq!(self.state, State::Assembling, "c_col_mut after factor");
        let b = &mut self.blocks[i];
        let n = b.band.n();
        &mut b.c[l * n..(l + 1) * n]
    }

    /// `E_i` (`m_i × n_i`): row `l` = border equation `border_i[l]`, column =
    /// block-local unknown. Stored row-major (`row_stride n_i`,
    /// `col_stride 1`), so each row is one contiguous slice.
    pub fn e_mut(&mut self, i: usize) -> MatMut<'_> {
        debug_assert_eq!(self.state, State::Assembling, "e_mut after factor");
        let b = &mut self.blocks[i];
        let (n, m) = (b.band.n(), b.border.len());
        MatMut::new(&mut b.e, m, n, n, 1)
    }

    /// Row `l` of `E_i` (length `n_i`).
    pub fn e_row_mut(&mut self, i: usize, l: usize) -> &mut [f64] {
        debug_assert_eq!(self.state, State::Assembling, "e_row_mut after factor");
        let b = &mut self.blocks[i];
        let n = b.band.n();
        &mut b.e[l * n..(l + 1) * n]
    }

    /// `D` (`k × k`), column-major (`row_stride 1`, `col_stride k`).
    /// Panics for a banded border ([`with_banded_border`](Self::with_banded_border));
    /// [`d_add`](Self::d_add) works for both.
    pub fn d_mut(&mut self) -> MatMut<'_> {
        debug_assert_eq!(self.state, State::Assembling, "d_mut after factor");
        let k = self.k;
        match &mut self.schur {
            Schur::Dense(d) => MatMut::new(d.as_mut_slice(), k, k, 1, k),
            Schur::Band(_) => panic!("d_mut on a banded border: use d_add"),
        }
    }

    /// `D[i, j] += v` (inside the band for a banded border).
    #[inline]
    pub fn d_add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert_eq!(self.state, State::Assembling, "d_add after factor");
        self.schur.add(i, j, v);
    }

    /// `D[i, j]` before [`factor`](Self::factor) (0 outside the band of
    /// a banded border); after it, the factors' storage.
    pub fn d_get(&self, i: usize, j: usize) -> f64 {
        self.schur.get(i, j)
    }

    /// Whether the border is in band storage.
    pub fn banded_border(&self) -> Option<(usize, usize)> {
        match &self.schur {
            Schur::Dense(_) => None,
            Schur::Band(b) => Some((b.kl(), b.ku())),
        }
    }

    /// `y = A x` with the unfactored matrix:
    /// `y_i = B_i x_i + C_i P_i x_b`, `y_b = Σ_i P_iᵀ E_i x_i + D x_b`.
    /// Panics if called after [`factor`](Self::factor) (the entries are then
    /// overwritten by the factors). Cost `O(Σ n_i (kl_i + ku_i + 2 m_i) + k²)`.
    pub fn mul_vec(
        &self,
        x_band: &[f64],
        x_border: &[f64],
        y_band: &mut [f64],
        y_border: &mut [f64],
    ) {
        assert_eq!(self.state, State::Assembling, "mul_vec after factor");
        assert_eq!(x_band.len(), self.n_band);
        assert_eq!(y_band.len(), self.n_band);
        assert_eq!(x_border.len(), self.k);
        assert_eq!(y_border.len(), self.k);
        y_band.fill(0.0);
        y_border.fill(0.0);
        self.schur.mul_vec_add(x_border, y_border);
        for b in &self.blocks {
            let n = b.band.n();
            let r = b.offset..b.offset + n;
            let (xi, yi) = (&x_band[r.clone()], &mut y_band[r]);
            b.band.mul_vec_add(xi, yi);
            for (l, &g) in b.border.iter().enumerate() {
                let xg = x_border[g];
                for (y, c) in yi.iter_mut().zip(&b.c[l * n..(l + 1) * n]) {
                    *y += c * xg;
                }
                y_border[g] += dot(&b.e[l * n..(l + 1) * n], xi);
            }
        }
    }

    /// Whether [`factor`](Self::factor) succeeded since the last
    /// [`clear`](Self::clear).
    pub fn is_factored(&self) -> bool {
        self.state == State::Factored
    }

    /// Factor `A` by block elimination, in place:
    /// `B_i = Π_i L_i U_i` ([`BandMatrix::factor`]), `C_i ← W_i = B_i⁻¹ C_i`
    /// (`m_i` band solves), `D ← S = D − Σ_i P_iᵀ (E_i W_i) P_i`
    /// (`(E_i W_i)_{ab}` scattered to `S[border_i[a], border_i[b]]`), then
    /// `S = Π_S L_S U_S` ([`DenseLu::factor`]). Cost
    /// `O(Σ n_i (kl_i+ku_i)(kl_i+m_i) + Σ n_i m_i² + k³)`, no allocation.
    ///
    /// Fails (with [`Part::Block`] or [`Part::Schur`]) on an exactly zero
    /// pivot or a non-finite value in any factor; a non-finite `C_i` or
    /// `E_i` shows up as non-finite `S`. After a failure, [`clear`](Self::clear)
    /// and refill before factoring again. See [`pivot_report`](Self::pivot_report)
    /// for near-singular matrices.
    pub fn factor(&mut self) -> Result<(), Singular> {
        assert_eq!(self.state, State::Assembling, "factor twice without clear");
        self.state = State::Failed;
        for (i, b) in self.blocks.iter_mut().enumerate() {
            b.band.factor().map_err(|e| e.with_part(Part::Block(i)))?;
            let (n, m) = (b.band.n(), b.border.len());
            b.band.solve_many(&mut b.c, m);
            for (a, &ga) in b.border.iter().enumerate() {
                let ea = &b.e[a * n..(a + 1) * n];
                for (l, &gl) in b.border.iter().enumerate() {
                    self.schur.add(ga, gl, -dot(ea, &b.c[l * n..(l + 1) * n]));
                }
            }
        }
        self.schur.factor().map_err(|e| e.with_part(Part::Schur))?;
        self.state = State::Factored;
        Ok(())
    }

    /// `x ← A⁻¹ x` in place (`x_band` holds `b_band` on entry, `x_border`
    /// holds `b_border`): `y_i = B_i⁻¹ b_i`,
    /// `x_b = S⁻¹ (b_b − Σ_i P_iᵀ E_i y_i)`, `x_i = y_i − W_i P_i x_b`.
    /// Panics unless factored. Cost `O(Σ n_i (2kl_i + ku_i + 2 m_i) + k²)`,
    /// no allocation. A non-finite right-hand side gives a non-finite
    /// solution (not checked).
    pub fn solve(&self, x_band: &mut [f64], x_border: &mut [f64]) {
        assert_eq!(
            self.state,
            State::Factored,
            "solve without a successful factor"
        );
        assert_eq!(x_band.len(), self.n_band);
        assert_eq!(x_border.len(), self.k);
        for b in &self.blocks {
            let n = b.band.n();
            let xi = &mut x_band[b.offset..b.offset + n];
            b.band.solve(xi);
            for (l, &g) in b.border.iter().enumerate() {
                x_border[g] -= dot(&b.e[l * n..(l + 1) * n], xi);
            }
        }
        self.schur.solve(x_border);
        for b in &self.blocks {
            let n = b.band.n();
            let xi = &mut x_band[b.offset..b.offset + n];
            for (l, &g) in b.border.iter().enumerate() {
                let xg = x_border[g];
                if xg != 0.0 {
                    for (x, w) in xi.iter_mut().zip(&b.c[l * n..(l + 1) * n]) {
                        *x -= w * xg;
                    }
                }
            }
        }
    }

    /// The sign of `det A` (`±1`) from the last successful
    /// [`factor`](Self::factor): block elimination gives
    /// `det A = Π_i det B_i · det S`, each sign from its LU
    /// ([`BandMatrix::det_sign`], [`DenseLu::det_sign`]). Panics unless
    /// factored. `O(Σ n_i + k)`, no allocation.
    pub fn det_sign(&self) -> f64 {
        assert_eq!(
            self.state,
            State::Factored,
            "det_sign without a successful factor"
        );
        self.blocks
            .iter()
            .map(|b| b.band.det_sign())
            .product::<f64>()
            * self.schur.det_sign()
    }

    /// Pivot statistics of the Schur complement factorization.
    pub fn schur_pivot_info(&self) -> PivotInfo {
        self.schur.pivot_info()
    }

    /// The smallest pivot ratio and the largest growth over all factors of
    /// the last successful [`factor`](Self::factor) (`O(N)`), for rejecting
    /// near-singular matrices: a `min_ratio` near `ε` means the solution has
    /// no correct digits.
    pub fn pivot_report(&self) -> PivotReport {
        let mut r = PivotReport {
            min_ratio: 1.0,
            min_ratio_part: Part::Schur,
            max_growth: 1.0,
            max_growth_part: Part::Schur,
        };
        let parts = self
            .blocks
            .iter()
            .enumerate()
            .map(|(i, b)| (Part::Block(i), b.band.pivot_info()))
            .chain(std::iter::once((Part::Schur, self.schur.pivot_info())));
        let mut first = true;
        for (part, info) in parts {
            let (ratio, growth) = (info.pivot_ratio(), info.growth());
            if first || ratio < r.min_ratio {
                r.min_ratio = ratio;
                r.min_ratio_part = part;
            }
            if first || growth > r.max_growth {
                r.max_growth = growth;
                r.max_growth_part = part;
            }
            first = false;
        }
        r
    }
}

#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
