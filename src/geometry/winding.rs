//! Inside tests for triangle meshes by the generalised winding number (Jacobson, Kavan and
//! Sorkine-Hornung 2013), accelerated by the hierarchical fast winding number of Barill,
//! Dickson, Schmidt, Levin and Jacobson (2018): a bounding-volume hierarchy whose far-away
//! nodes are replaced by their dipole expansion (second order), while nearby leaves are summed
//! exactly as signed solid angles.
//!
//! The winding number is 1 inside a closed, outward-oriented surface and 0 outside; across a
//! small hole it varies smoothly instead of leaking, so `|w| > ½` classifies points of real,
//! imperfect meshes robustly (an inward-oriented mesh gives −1, which counts as inside too).

use std::f64::consts::PI;

type V3 = [f64; 3];

fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}

/// Nodes whose expansion centre is farther than `BETA` times their radius from the query use
/// the far-field expansion (Barill et al. use β = 2).
const BETA: f64 = 2.0;
/// Triangles per leaf at most.
const LEAF: usize = 4;
const NONE: u32 = u32::MAX;

/// The signed solid angle of triangle `(a, b, c)` seen from `q` (Van Oosterom and Strackee
/// 1983), positive when the triangle's front (counter-clockwise) side faces away from `q`.
pub fn solid_angle(a: V3, b: V3, c: V3, q: V3) -> f64 {
    let (a, b, c) = (sub(a, q), sub(b, q), sub(c, q));
    let (la, lb, lc) = (norm(a), norm(b), norm(c));
    let det = dot(a, cross(b, c));
    let den = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
    2.0 * det.atan2(den)
}

#[derive(Clone, Debug)]
struct Node {
    /// Area-weighted centroid of the node's triangles: the expansion centre p̃.
    center: V3,
    /// β times the largest distance from `center` to a vertex of the node's triangles, squared.
    far2: f64,
    /// The largest distance from `center` to a vertex of the node's triangles.
    radius: f64,
    /// Σ aₜ nₜ: the dipole moment (first order).
    n: V3,
    /// Σ aₜ nₜ ⊗ (cₜ − p̃), row i column j: the second-order moment.
    m: [V3; 3],
    /// The node's triangles: `tris[start..start + count]` (contiguous for every node).
    start: u32,
    count: u32,
    /// Children (`NONE` for a leaf).
    left: u32,
    right: u32,
}

/// A triangle soup prepared for fast winding-number queries.
#[derive(Clone, Debug, Default)]
pub struct WindingTree {
    nodes: Vec<Node>,
    /// Triangle corners in leaf order.
    tris: Vec<[V3; 3]>,
}

impl WindingTree {
    /// Builds the hierarchy over triangles given by vertex positions and index triples
    /// (indices must be in range).
    pub fn new(vertices: &[V3], triangles: &[[u32; 3]]) -> Self {
        let mut tris: Vec<[V3; 3]> = triangles
            .iter()
            .map(|t| t.map(|i| vertices[i as usize]))
            .collect();
        let mut nodes = Vec::with_capacity(2 * tris.len() / LEAF + 1);
        if !tris.is_empty() {
            let n = tris.len();
            build(&mut nodes, &mut tris, 0, n);
        }
        WindingTree { nodes, tris }
    }

    pub fn triangle_count(&self) -> usize {
        self.tris.len()
    }

    /// The exact generalised winding number at `q`: Σ Ωₜ / 4π over every triangle.
    pub fn winding_number_exact(&self, q: V3) -> f64 {
        self.tris
            .iter()
            .map(|t| solid_angle(t[0], t[1], t[2], q))
            .sum::<f64>()
            / (4.0 * PI)
    }

    /// The winding number at `q` by the hierarchical approximation: exact near the surface,
    /// second-order accurate in (node size / distance) far from it.
    pub fn winding_number(&self, q: V3) -> f64 {
        if self.nodes.is_empty() {
            return 0.0;
        }
        let mut w = 0.0;
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            let r = sub(node.center, q);
            let d2 = dot(r, r);
            if d2 > node.far2 {
                let inv = 1.0 / d2.sqrt();
                let inv3 = inv * inv * inv;
                let first = dot(node.n, r) * inv3;
                let m = &node.m;
                let trace = m[0][0] + m[1][1] + m[2][2];
                let mr = [dot(m[0], r), dot(m[1], r), dot(m[2], r)];
                let second = trace * inv3 - 3.0 * dot(r, mr) * inv3 * inv * inv;
                w += first + second;
            } else if node.left != NONE && top + 2 <= stack.len() {
                stack[top] = node.right;
                stack[top + 1] = node.left;
                top += 2;
            } else {
                // a leaf (or, never for a median-split tree, a stack overflow): sum exactly
                let s = node.start as usize;
                for t in &self.tris[s..s + node.count as usize] {
                    w += solid_angle(t[0], t[1], t[2], q);
                }
            }
        }
        w / (4.0 * PI)
    }

    /// Whether some triangle may come within `rho` of `c` (conservative: tested with
    /// bounding spheres, so it may say yes when no triangle is that close, never the reverse).
    pub fn near_surface(&self, c: V3, rho: f64) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            let d = norm(sub(node.center, c));
            if d > rho + node.radius {
                continue;
            }
            if node.left != NONE && top + 2 <= stack.len() {
                stack[top] = node.right;
                stack[top + 1] = node.left;
                top += 2;
            } else {
                let s = node.start as usize;
                for t in &self.tris[s..s + node.count as usize] {
                    let m = centroid(t);
                    let r = t.iter().map(|v| norm(sub(*v, m))).fold(0.0, f64::max);
                    if norm(sub(m, c)) <= rho + r {
                        return true;
                    }
                }
            }
        }
        false
    }

    /// Whether `q` is inside: |w| > ½.
    pub fn contains(&self, q: V3) -> bool {
        self.winding_number(q).abs() > 0.5
    }
}

/// Builds the subtree over `tris[start..start + count]` and returns its node index.
fn build(nodes: &mut Vec<Node>, tris: &mut [[V3; 3]], start: usize, count: usize) -> u32 {
    let slice = &tris[start..start + count];
    // moments
    let mut area_sum = 0.0;
    let mut weighted = [0.0; 3];
    let mut plain = [0.0; 3];
    let mut n = [0.0; 3];
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for t in slice {
        let c = centroid(t);
        let an = area_vector(t);
        let a = norm(an);
        area_sum += a;
        for k in 0..3 {
            weighted[k] += a * c[k];
            plain[k] += c[k];
            n[k] += an[k];
            lo[k] = lo[k].min(c[k]);
            hi[k] = hi[k].max(c[k]);
        }
    }
    let center: V3 = if area_sum > 0.0 {
        weighted.map(|x| x / area_sum)
    } else {
        plain.map(|x| x / count as f64)
    };
    let mut m = [[0.0; 3]; 3];
    let mut radius2: f64 = 0.0;
    for t in slice {
        let d = sub(centroid(t), center);
        let an = area_vector(t);
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] += an[i] * d[j];
            }
        }
        for v in t {
            let e = sub(*v, center);
            radius2 = radius2.max(dot(e, e));
        }
    }
    let index = nodes.len();
    nodes.push(Node {
        center,
        far2: BETA * BETA * radius2,
        radius: radius2.sqrt(),
        n,
        m,
        start: start as u32,
        count: count as u32,
        left: NONE,
        right: NONE,
    });
    if count > LEAF {
        // split at the median centroid along the longest axis of the centroids' box
        let axis = (0..3)
            .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
            .unwrap_or(0);
        let half = count / 2;
        tris[start..start + count]
            .select_nth_unstable_by(half, |a, b| centroid(a)[axis].total_cmp(&centroid(b)[axis]));
        let left = build(nodes, tris, start, half);
        let right = build(nodes, tris, start + half, count - half);
        let node = &mut nodes[index];
        node.left = left;
        node.right = right;
    }
    index as u32
}

fn centroid(t: &[V3; 3]) -> V3 {
    std::array::from_fn(|k| (t[0][k] + t[1][k] + t[2][k]) / 3.0)
}

/// ½ (b − a) × (c − a): the triangle's area times its unit normal.
fn area_vector(t: &[V3; 3]) -> V3 {
    cross(sub(t[1], t[0]), sub(t[2], t[0])).map(|x| 0.5 * x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A UV sphere of radius `r` about `c`, outward oriented.
    pub fn sphere(c: V3, r: f64, rings: usize, sectors: usize) -> (Vec<V3>, Vec<[u32; 3]>) {
        let mut v = vec![[c[0], c[1] + r, c[2]]];
        for i in 1..rings {
            let th = PI * i as f64 / rings as f64;
            for j in 0..sectors {
                let ph = 2.0 * PI * j as f64 / sectors as f64;
                v.push([
                    c[0] + r * th.sin() * ph.cos(),
                    c[1] + r * th.cos(),
                    c[2] - r * th.sin() * ph.sin(),
                ]);
            }
        }
        v.push([c[0], c[1] - r, c[2]]);
        let bottom = (v.len() - 1) as u32;
        let ring = |i: usize, j: usize| (1 + (i - 1) * sectors + j % sectors) as u32;
        let mut t = Vec::new();
        for j in 0..sectors {
            t.push([0, ring(1, j), ring(1, j + 1)]);
            t.push([bottom, ring(rings - 1, j + 1), ring(rings - 1, j)]);
        }
        for i in 1..rings - 1 {
            for j in 0..sectors {
                t.push([ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)]);
                t.push([ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)]);
            }
        }
        (v, t)
    }

    #[test]
    fn a_closed_sphere_has_winding_number_one_inside_and_zero_outside() {
        let (v, t) = sphere([0.1, 0.2, 0.3], 1.0, 24, 48);
        let tree = WindingTree::new(&v, &t);
        for q in [[0.1, 0.2, 0.3], [0.5, 0.4, 0.3], [0.1, -0.6, 0.5]] {
            let w = tree.winding_number_exact(q);
            assert!((w - 1.0).abs() < 1e-9, "{q:?}: {w}");
            let fast = tree.winding_number(q);
            assert!((fast - 1.0).abs() < 0.1, "{q:?}: {fast}");
        }
        for q in [[2.0, 0.0, 0.0], [0.1, 1.3, 0.3], [30.0, -20.0, 5.0]] {
            assert!(tree.winding_number_exact(q).abs() < 1e-9);
            assert!(tree.winding_number(q).abs() < 0.1);
        }
    }

    #[test]
    fn the_fast_sum_agrees_with_the_exact_one() {
        let (v, t) = sphere([0.0; 3], 0.5, 40, 80);
        let tree = WindingTree::new(&v, &t);
        let mut worst: f64 = 0.0;
        let mut state = 1u64;
        for _ in 0..2000 {
            let q: V3 = std::array::from_fn(|_| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.4 - 1.2
            });
            let (fast, exact) = (tree.winding_number(q), tree.winding_number_exact(q));
            worst = worst.max((fast - exact).abs());
            assert_eq!(fast.abs() > 0.5, exact.abs() > 0.5, "{q:?}");
        }
        // second order at β = 2: below a tenth, far from the ½ threshold
        assert!(worst < 0.1, "largest difference {worst}");
    }

    #[test]
    fn a_hole_does_not_leak() {
        let (v, mut t) = sphere([0.0; 3], 1.0, 24, 48);
        // punch a hole: remove the triangles around the north pole
        t.retain(|tri| !tri.contains(&0));
        let tree = WindingTree::new(&v, &t);
        assert!(tree.contains([0.0, 0.0, 0.0]));
        assert!(tree.contains([0.0, 0.6, 0.0]));
        assert!(!tree.contains([0.0, 1.5, 0.0]));
        // inward orientation counts as inside too
        let flipped: Vec<[u32; 3]> = t.iter().map(|&[a, b, c]| [a, c, b]).collect();
        let tree = WindingTree::new(&v, &flipped);
        assert!(tree.winding_number([0.0; 3]) < -0.9);
        assert!(tree.contains([0.0; 3]));
    }
}
