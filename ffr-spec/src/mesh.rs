//! Elastic coordinates of a body made of `N` equal elements: the element's
//! nodal coordinates, the reference condition that removes rigid-body motion,
//! and the resulting numbering of `q_f` (node by node, each node's coordinates
//! in the shape's order, removed ones left out).

use std::fmt;
use std::str::FromStr;

/// The most elements a body may have.
pub const MAX_ELEMENTS: usize = 256;

/// What an elastic coordinate is: a translation or rotation of its node.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Kind {
    /// Translation along body x.
    Ux,
    /// Translation along body y.
    Uy,
    /// Translation along body z.
    Uz,
    /// Rotation about body x (torsion).
    Rx,
    /// Rotation about body y.
    Ry,
    /// Rotation about body z.
    Rz,
}

impl Kind {
    /// All kinds with their names.
    pub const ALL: [(Kind, &'static str); 6] = [
        (Kind::Ux, "ux"),
        (Kind::Uy, "uy"),
        (Kind::Uz, "uz"),
        (Kind::Rx, "rx"),
        (Kind::Ry, "ry"),
        (Kind::Rz, "rz"),
    ];

    /// The kind's name as written in shape files and labels.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Ux => "ux",
            Kind::Uy => "uy",
            Kind::Uz => "uz",
            Kind::Rx => "rx",
            Kind::Ry => "ry",
            Kind::Rz => "rz",
        }
    }

    /// The kind named `name`.
    pub fn from_name(name: &str) -> Option<Kind> {
        Kind::ALL.iter().find(|(_, n)| *n == name).map(|(k, _)| *k)
    }

    /// Whether the kind exists in a planar (x–y) shape.
    pub fn is_planar(self) -> bool {
        matches!(self, Kind::Ux | Kind::Uy | Kind::Rz)
    }

    /// Whether this is a translation.
    pub fn is_translation(self) -> bool {
        matches!(self, Kind::Ux | Kind::Uy | Kind::Uz)
    }

    /// The body axis (0, 1, 2 for x, y, z) of the translation or rotation.
    pub fn axis(self) -> usize {
        match self {
            Kind::Ux | Kind::Rx => 0,
            Kind::Uy | Kind::Ry => 1,
            Kind::Uz | Kind::Rz => 2,
        }
    }
}

impl fmt::Display for Kind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// How the body frame is fixed to the body (which nodal coordinates are removed).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Reference {
    /// Cantilever: every coordinate of node 0 removed.
    Clamped,
    /// Simply supported: node 0's translations, node N's transverse
    /// translations and, in space, node 0's torsion rotation removed.
    Pinned,
    /// Nothing removed (inertia checks, modal bases): `K_ff` is singular.
    Free,
}

impl Reference {
    /// Every reference condition, with its name.
    pub const ALL: [(Reference, &'static str); 3] = [
        (Reference::Clamped, "clamped"),
        (Reference::Pinned, "pinned"),
        (Reference::Free, "free"),
    ];

    /// Whether the condition removes `kind` at body node `node` of a body
    /// with `elements` elements and shape dimension `dim`.
    pub fn removes(self, node: usize, kind: Kind, elements: usize, dim: usize) -> bool {
        match self {
            Reference::Free => false,
            Reference::Clamped => node == 0,
            Reference::Pinned => {
                (node == 0 && (kind.is_translation() || (dim == 3 && kind == Kind::Rx)))
                    || (node == elements && matches!(kind, Kind::Uy | Kind::Uz))
            }
        }
    }
}

impl FromStr for Reference {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Reference::ALL
            .iter()
            .find(|(_, n)| *n == s)
            .map(|(r, _)| *r)
            .ok_or_else(|| {
                format!("unknown reference condition `{s}`: expected clamped, pinned or free")
            })
    }
}

impl fmt::Display for Reference {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Reference::Clamped => "clamped",
            Reference::Pinned => "pinned",
            Reference::Free => "free",
        })
    }
}

/// One coordinate of an element (a column of its shape matrix `S`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ElementCoordinate {
    /// End node: 0 at `ξ = 0`, 1 at `ξ = 1`.
    pub node: u8,
    /// Which nodal quantity it is.
    pub kind: Kind,
}

/// An elastic coordinate of a body: a nodal quantity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Dof {
    /// Body node, `0..=N`.
    pub node: usize,
    /// Which quantity.
    pub kind: Kind,
}

impl fmt::Display for Dof {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}_{}", self.kind, self.node)
    }
}

/// A mesh that cannot be built.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MeshError(pub String);

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for MeshError {}

/// The nodes of a graded mesh checked: 2 to `MAX_ELEMENTS + 1`, finite, the
/// first at 0, the last at `length`, strictly increasing (the scene reader
/// and the runtime's `KernelBody::with_nodes` both check through this).
pub fn check_nodes(nodes: &[f64], length: f64) -> Result<(), MeshError> {
    let n = nodes.len();
    if !(2..=MAX_ELEMENTS + 1).contains(&n) {
        return Err(MeshError(format!(
            "a mesh needs 2 to {} nodes (1 to {MAX_ELEMENTS} elements), found {n}",
            MAX_ELEMENTS + 1
        )));
    }
    if let Some((i, x)) = nodes.iter().enumerate().find(|(_, x)| !x.is_finite()) {
        return Err(MeshError(format!(
            "node {i} is at x = {x:?}: nodes must be finite"
        )));
    }
    if nodes[0] != 0.0 {
        return Err(MeshError(format!(
            "the first node is at x = {:?}: a mesh starts at the body's root, x = 0",
            nodes[0]
        )));
    }
    if nodes[n - 1] != length {
        return Err(MeshError(format!(
            "the last node is at x = {:?}: a mesh ends at the body's length, x = L = {length:?} m",
            nodes[n - 1]
        )));
    }
    if let Some(i) = (1..n).find(|&i| nodes[i] <= nodes[i - 1]) {
        return Err(MeshError(format!(
            "nodes {} and {i} are at x = {:?} and x = {:?}: nodes must increase strictly",
            i - 1,
            nodes[i - 1],
            nodes[i]
        )));
    }
    Ok(())
}

/// `N` equal elements along body x from node 0 (the body-frame origin) to
/// node `N`, sharing nodal coordinates, with a reference condition.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mesh {
    coordinates: Vec<ElementCoordinate>,
    dim: usize,
    elements: usize,
    reference: Reference,
    dofs: Vec<Dof>,
    /// `elements × n_e` body indices, `usize::MAX` where removed.
    maps: Vec<usize>,
}

/// Marks a removed coordinate in [`Mesh::element_map`].
const REMOVED: usize = usize::MAX;

impl Mesh {
    /// The mesh of `elements` elements with the given element coordinates
    /// (both ends must carry the same kinds), shape dimension `dim` and
    /// reference condition.
    pub fn new(
        coordinates: &[ElementCoordinate],
        dim: usize,
        elements: usize,
        reference: Reference,
    ) -> Result<Mesh, MeshError> {
        if elements == 0 {
            return Err(MeshError("elements must be at least 1, found 0".into()));
        }
        if elements > MAX_ELEMENTS {
            return Err(MeshError(format!(
                "elements must be at most {MAX_ELEMENTS}, found {elements}"
            )));
        }
        if dim != 2 && dim != 3 {
            return Err(MeshError(format!("dimension must be 2 or 3, found {dim}")));
        }
        let kinds_at = |n: u8| {
            let mut k: Vec<Kind> = coordinates
                .iter()
                .filter(|c| c.node == n)
                .map(|c| c.kind)
                .collect();
            k.sort();
            k
        };
        if coordinates.is_empty() || kinds_at(0) != kinds_at(1) {
            return Err(MeshError(
                "an element needs the same coordinate kinds at both ends".into(),
            ));
        }
        if coordinates.iter().any(|c| c.node > 1) {
            return Err(MeshError("element nodes are 0 and 1".into()));
        }
        let node_kinds: Vec<Kind> = coordinates
            .iter()
            .filter(|c| c.node == 0)
            .map(|c| c.kind)
            .collect();
        let dofs: Vec<Dof> = (0..=elements)
            .flat_map(|node| node_kinds.iter().map(move |&kind| Dof { node, kind }))
            .filter(|d| !reference.removes(d.node, d.kind, elements, dim))
            .collect();
        let mut maps = Vec::with_capacity(elements * coordinates.len());
        for e in 0..elements {
            for c in coordinates {
                let node = e + c.node as usize;
                maps.push(
                    dofs.iter()
                        .position(|d| d.node == node && d.kind == c.kind)
                        .unwrap_or(REMOVED),
                );
            }
        }
        Ok(Mesh {
            coordinates: coordinates.to_vec(),
            dim,
            elements,
            reference,
            dofs,
            maps,
        })
    }

    /// Number of elements `N`.
    pub fn elements(&self) -> usize {
        self.elements
    }

    /// The reference condition.
    pub fn reference(&self) -> Reference {
        self.reference
    }

    /// Shape dimension (2 or 3).
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Element coordinates `n_e`.
    pub fn n_local(&self) -> usize {
        self.coordinates.len()
    }

    /// The element's coordinates.
    pub fn coordinates(&self) -> &[ElementCoordinate] {
        &self.coordinates
    }

    /// The elastic coordinates in body order.
    pub fn dofs(&self) -> &[Dof] {
        &self.dofs
    }

    /// Number of elastic coordinates `n_f`.
    pub fn nf(&self) -> usize {
        self.dofs.len()
    }

    /// For element `e`, the body index of each element coordinate (`None`
    /// where the reference condition removed it).
    pub fn element_map(&self, e: usize) -> impl Iterator<Item = Option<usize>> + '_ {
        let n = self.coordinates.len();
        self.maps[e * n..(e + 1) * n]
            .iter()
            .map(|&i| (i != REMOVED).then_some(i))
    }

    /// The body index of coordinate `kind` at node `node`, if it exists.
    pub fn dof_index(&self, node: usize, kind: Kind) -> Option<usize> {
        self.dofs
            .iter()
            .position(|d| d.node == node && d.kind == kind)
    }

    /// Half-bandwidth of every matrix assembled from element matrices:
    /// the largest `|i − j|` of two coordinates of one element.
    pub fn half_bandwidth(&self) -> usize {
        (0..self.elements)
            .map(|e| {
                let idx: Vec<usize> = self.element_map(e).flatten().collect();
                let (lo, hi) = (idx.iter().min(), idx.iter().max());
                match (lo, hi) {
                    (Some(a), Some(b)) => b - a,
                    _ => 0,
                }
            })
            .max()
            .unwrap_or(0)
    }

    /// Undeformed x of body node `node` for a body of length `length`.
    pub fn node_x(&self, node: usize, length: f64) -> f64 {
        length * node as f64 / self.elements as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn beam2() -> Vec<ElementCoordinate> {
        [0u8, 1]
            .iter()
            .flat_map(|&node| {
                [Kind::Ux, Kind::Uy, Kind::Rz]
                    .into_iter()
                    .map(move |kind| ElementCoordinate { node, kind })
            })
            .collect()
    }

    #[test]
    fn numbering_and_bandwidth() {
        let m = Mesh::new(&beam2(), 2, 3, Reference::Clamped).unwrap();
        assert_eq!(m.nf(), 9);
        assert_eq!(m.dofs()[0].to_string(), "ux_1");
        assert_eq!(
            m.element_map(0).collect::<Vec<_>>(),
            [None, None, None, Some(0), Some(1), Some(2)]
        );
        assert_eq!(
            m.element_map(2).collect::<Vec<_>>(),
            [3, 4, 5, 6, 7, 8].map(Some)
        );
        assert_eq!(m.half_bandwidth(), 5);
        let p = Mesh::new(&beam2(), 2, 2, Reference::Pinned).unwrap();
        let labels: Vec<String> = p.dofs().iter().map(|d| d.to_string()).collect();
        assert_eq!(labels, ["rz_0", "ux_1", "uy_1", "rz_1", "ux_2", "rz_2"]);
        assert_eq!(p.dof_index(2, Kind::Uy), None);
        let f = Mesh::new(&beam2(), 2, 1, Reference::Free).unwrap();
        assert_eq!(f.nf(), 6);
        assert!(Mesh::new(&beam2(), 2, 0, Reference::Free).is_err());
        assert!(Mesh::new(&beam2(), 2, MAX_ELEMENTS + 1, Reference::Free).is_err());
    }
}
