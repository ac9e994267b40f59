//! A bandwidth-reducing ordering of a symmetric sparsity pattern: reverse
//! Cuthill–McKee (Cuthill & McKee 1969; George & Liu, *Computer Solution of
//! Large Sparse Positive Definite Systems*, 1981, §4.3), with a
//! pseudo-peripheral start node per connected component (George & Liu's
//! algorithm of §4.3.2).
//!
//! The assembly orders the border of its [`super::BorderedSystem`] with it:
//! a chain of bodies joined end to end (a segmented beam) couples each
//! body's border unknowns only to its neighbours', so in this order the
//! border's Schur complement is banded and its factorization costs
//! `O(k b²)` instead of `O(k³)` (`b` the bandwidth, `k` the border size).
//!
//! Why not a crate: `sprs` has the same algorithm but brings `ndarray` and
//! its sparse matrix types into the runtime for a few dozen lines on graphs
//! of a few hundred nodes; `nalgebra-sparse` and `faer` have fill-reducing
//! orderings (AMD) for sparse factorizations, not bandwidth reduction.

/// The reverse Cuthill–McKee order of the graph with adjacency lists
/// `adj` (node `i`'s neighbours; symmetric, no self loops needed):
/// `order[p]` is the node at position `p`.
pub fn reverse_cuthill_mckee(adj: &[Vec<usize>]) -> Vec<usize> {
    let n = adj.len();
    let degree: Vec<usize> = adj.iter().map(Vec::len).collect();
    let mut placed = vec![false; n];
    let mut order = Vec::with_capacity(n);
    let mut level = vec![usize::MAX; n];
    loop {
        // The unplaced node of least degree (lowest index on ties) starts a
        // component; move it to a pseudo-peripheral node of its component.
        let Some(seed) = (0..n)
            .filter(|&i| !placed[i])
            .min_by_key(|&i| (degree[i], i))
        else {
            break;
        };
        let start = pseudo_peripheral(adj, &degree, seed, &mut level);
        let first = order.len();
        order.push(start);
        placed[start] = true;
        let mut head = first;
        while head < order.len() {
            let v = order[head];
            head += 1;
            let mut next: Vec<usize> = adj[v].iter().copied().filter(|&u| !placed[u]).collect();
            next.sort_by_key(|&u| (degree[u], u));
            next.dedup();
            for u in next {
                placed[u] = true;
                order.push(u);
            }
        }
    }
    order.reverse();
    order
}

/// George & Liu's pseudo-peripheral node of `seed`'s component: repeat a
/// breadth-first search from the node of least degree in the last level
/// while the number of levels grows.
fn pseudo_peripheral(
    adj: &[Vec<usize>],
    degree: &[usize],
    seed: usize,
    level: &mut [usize],
) -> usize {
    let mut start = seed;
    let mut depth = levels(adj, start, level);
    loop {
        let last = level
            .iter()
            .enumerate()
            .filter(|(_, &l)| l == depth)
            .map(|(i, _)| i)
            .min_by_key(|&i| (degree[i], i))
            .expect("a breadth-first search reaches its own last level");
        let d = levels(adj, last, level);
        if d <= depth {
            // Leave `level` as the search from `start` left it for nothing
            // else: only the start matters.
            return start;
        }
        start = last;
        depth = d;
    }
}

/// Breadth-first levels from `start` into `level` (`usize::MAX`:
/// unreached); returns the deepest level.
fn levels(adj: &[Vec<usize>], start: usize, level: &mut [usize]) -> usize {
    level.iter_mut().for_each(|l| *l = usize::MAX);
    level[start] = 0;
    let mut queue = std::collections::VecDeque::from([start]);
    let mut depth = 0;
    while let Some(v) = queue.pop_front() {
        for &u in &adj[v] {
            if level[u] == usize::MAX {
                level[u] = level[v] + 1;
                depth = depth.max(level[u]);
                queue.push_back(u);
            }
        }
    }
    depth
}

/// The half-bandwidth `max |p(i) − p(j)|` over the edges `i — j` of `adj`
/// when node `i` sits at position `pos[i]`.
pub fn bandwidth(adj: &[Vec<usize>], pos: &[usize]) -> usize {
    adj.iter()
        .enumerate()
        .flat_map(|(i, nb)| nb.iter().map(move |&j| pos[i].abs_diff(pos[j])))
        .max()
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn graph(n: usize, edges: &[(usize, usize)]) -> Vec<Vec<usize>> {
        let mut adj = vec![Vec::new(); n];
        for &(a, b) in edges {
            adj[a].push(b);
            adj[b].push(a);
        }
        adj
    }

    fn positions(order: &[usize]) -> Vec<usize> {
        let mut pos = vec![0; order.len()];
        for (p, &i) in order.iter().enumerate() {
            pos[i] = p;
        }
        pos
    }

    #[test]
    fn a_shuffled_path_becomes_tridiagonal() {
        // The path 0 — 5 — 2 — 7 — 1 — 6 — 3 — 4 numbered at random.
        let path = [0, 5, 2, 7, 1, 6, 3, 4];
        let edges: Vec<_> = path.windows(2).map(|w| (w[0], w[1])).collect();
        let adj = graph(8, &edges);
        let order = reverse_cuthill_mckee(&adj);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..8).collect::<Vec<_>>(), "a permutation");
        assert_eq!(bandwidth(&adj, &positions(&order)), 1);
        // In the natural numbering the widest edge is 7 — 1.
        assert_eq!(bandwidth(&adj, &(0..8).collect::<Vec<_>>()), 6);
    }

    #[test]
    fn a_chain_of_cliques_is_banded_and_components_are_kept() {
        // Cliques of 5 sharing one node each, numbered interleaved, plus an
        // isolated node and a separate pair.
        let k = 6;
        let mut edges = Vec::new();
        let node = |c: usize, i: usize| if i == 0 { c } else { k + 1 + 4 * c + i - 1 };
        for c in 0..k {
            let members: Vec<usize> = (0..5)
                .map(|i| if i == 4 { node(c + 1, 0) } else { node(c, i) })
                .collect();
            for a in 0..5 {
                for b in a + 1..5 {
                    edges.push((members[a], members[b]));
                }
            }
        }
        let n = k + 1 + 4 * k + 3;
        edges.push((n - 2, n - 1));
        let adj = graph(n, &edges);
        let order = reverse_cuthill_mckee(&adj);
        assert_eq!(order.len(), n);
        let b = bandwidth(&adj, &positions(&order));
        assert!(b <= 7, "bandwidth {b}");
    }
}
