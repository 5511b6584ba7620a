//! Building the hierarchy (binned SAH) and walking it (iterative, nearer child first).

use crate::triangle::ShearedRay;
use crate::{Ray, SceneBvh, WorldTriangle};

/// Bins per axis of the surface-area heuristic.
const BINS: usize = 16;
/// Largest leaf the heuristic may choose (bigger ones only for identical centroids
/// below [`MEDIAN_SPLIT_DEPTH`], which never happens beyond it).
const MAX_LEAF: usize = 4;
/// The traversal's fixed stack; the build keeps the depth below it.
const STACK: usize = 96;
/// Below this depth the build splits at the median instead (halving every level), so a
/// pathological distribution that the heuristic peels one triangle at a time still
/// ends within `MEDIAN_SPLIT_DEPTH + 32 < STACK` levels.
const MEDIAN_SPLIT_DEPTH: usize = 56;
/// Relative cost of visiting a node against testing one triangle.
const TRAVERSAL_COST: f64 = 1.0;
/// Boxes are widened by this fraction of their largest coordinate magnitude, and slab
/// distances by 2γ₃ (Ize, "Robust BVH Ray Traversal", 2013), so a box test never
/// rejects a ray that the (rounded) triangle test would accept.
const BOX_PADDING: f64 = 1e-12;
const SLAB_ROUNDING: f64 = 2.0 * GAMMA_3;
/// γ₃ = 3u/(1 − 3u), u the unit roundoff (half of `f64::EPSILON`).
const GAMMA_3: f64 = 3.0 * UNIT_ROUNDOFF / (1.0 - 3.0 * UNIT_ROUNDOFF);
const UNIT_ROUNDOFF: f64 = f64::EPSILON / 2.0;

/// One node: its box, and either a leaf's triangles (`count > 0`: `count` triangles
/// from `first`) or an interior node's two children (`count == 0`: nodes `first` and
/// `first + 1`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Node {
    min: [f64; 3],
    max: [f64; 3],
    first: u32,
    count: u32,
}

#[derive(Clone, Copy)]
struct Aabb {
    min: [f64; 3],
    max: [f64; 3],
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        min: [f64::INFINITY; 3],
        max: [f64::NEG_INFINITY; 3],
    };

    fn grow_point(&mut self, p: [f64; 3]) {
        self.grow(&Aabb { min: p, max: p });
    }

    fn grow(&mut self, other: &Aabb) {
        for axis in 0..3 {
            self.min[axis] = self.min[axis].min(other.min[axis]);
            self.max[axis] = self.max[axis].max(other.max[axis]);
        }
    }

    /// Half the surface area (the heuristic only compares areas); 0 when empty.
    fn half_area(&self) -> f64 {
        let d = [0, 1, 2].map(|axis| (self.max[axis] - self.min[axis]).max(0.0));
        d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
    }

    fn padded(&self) -> ([f64; 3], [f64; 3]) {
        let magnitude = (0..3)
            .map(|axis| self.min[axis].abs().max(self.max[axis].abs()))
            .fold(0.0, f64::max);
        let pad = magnitude * BOX_PADDING;
        (self.min.map(|c| c - pad), self.max.map(|c| c + pad))
    }
}

/// The triangles reordered into leaf order, and the nodes (root first).
pub(crate) fn build(triangles: Vec<WorldTriangle>) -> (Vec<WorldTriangle>, Vec<Node>) {
    if triangles.is_empty() {
        return (triangles, Vec::new());
    }
    let boxes: Vec<Aabb> = triangles
        .iter()
        .map(|t| {
            let mut b = Aabb::EMPTY;
            t.vertices.iter().for_each(|&p| b.grow_point(p));
            b
        })
        .collect();
    let centroids: Vec<[f64; 3]> = boxes
        .iter()
        .map(|b| [0, 1, 2].map(|axis| 0.5 * (b.min[axis] + b.max[axis])))
        .collect();
    let mut order: Vec<u32> = (0..triangles.len() as u32).collect();
    let mut nodes = vec![Node {
        min: [0.0; 3],
        max: [0.0; 3],
        first: 0,
        count: 0,
    }];
    // (node, range of `order`, depth)
    let mut work = vec![(0usize, 0usize, triangles.len(), 0usize)];
    while let Some((node, start, end, depth)) = work.pop() {
        let items = &mut order[start..end];
        let mut bounds = Aabb::EMPTY;
        let mut centroid_bounds = Aabb::EMPTY;
        for &i in items.iter() {
            bounds.grow(&boxes[i as usize]);
            centroid_bounds.grow_point(centroids[i as usize]);
        }
        let (min, max) = bounds.padded();
        nodes[node].min = min;
        nodes[node].max = max;
        let count = end - start;
        let leaf = |nodes: &mut Vec<Node>| {
            nodes[node].first = start as u32;
            nodes[node].count = count as u32;
        };
        if count <= 1 {
            leaf(&mut nodes);
            continue;
        }
        let split = if depth >= MEDIAN_SPLIT_DEPTH {
            Some(median_split(items, &centroids, &centroid_bounds))
        } else {
            match sah_split(items, &boxes, &centroids, &centroid_bounds, &bounds) {
                Some(mid) => Some(mid),
                None if count > MAX_LEAF => Some(median_split(items, &centroids, &centroid_bounds)),
                None => None,
            }
        };
        let Some(mid) = split else {
            leaf(&mut nodes);
            continue;
        };
        let left = nodes.len();
        nodes.push(nodes[node]);
        nodes.push(nodes[node]);
        nodes[node].first = left as u32;
        nodes[node].count = 0;
        work.push((left, start, start + mid, depth + 1));
        work.push((left + 1, start + mid, end, depth + 1));
    }
    let mut slots: Vec<Option<WorldTriangle>> = triangles.into_iter().map(Some).collect();
    let ordered = order
        .iter()
        .filter_map(|&i| slots[i as usize].take())
        .collect();
    (ordered, nodes)
}

/// The best binned-SAH split of `items` (reordered so the left part comes first) as the
/// left part's length, or `None` when a leaf is cheaper (only for at most [`MAX_LEAF`]
/// items) or every centroid is the same point.
// `axis` indexes the centroids, both boxes' corners and the best split's record.
#[allow(clippy::needless_range_loop)]
fn sah_split(
    items: &mut [u32],
    boxes: &[Aabb],
    centroids: &[[f64; 3]],
    centroid_bounds: &Aabb,
    bounds: &Aabb,
) -> Option<usize> {
    let count = items.len();
    let mut best: Option<(f64, usize, usize)> = None; // (cost, axis, first bin on the right)
    for axis in 0..3 {
        let low = centroid_bounds.min[axis];
        let extent = centroid_bounds.max[axis] - low;
        if extent.is_nan() || extent <= 0.0 {
            continue;
        }
        let scale = BINS as f64 / extent;
        let bin_of = |c: f64| (((c - low) * scale) as usize).min(BINS - 1);
        let mut bin_boxes = [Aabb::EMPTY; BINS];
        let mut bin_counts = [0usize; BINS];
        for &i in items.iter() {
            let bin = bin_of(centroids[i as usize][axis]);
            bin_boxes[bin].grow(&boxes[i as usize]);
            bin_counts[bin] += 1;
        }
        // Areas and counts of every prefix (left of a split) and suffix (right of it).
        let mut right_area = [0.0; BINS];
        let mut right_count = [0usize; BINS];
        let mut grown = Aabb::EMPTY;
        let mut n = 0;
        for bin in (1..BINS).rev() {
            grown.grow(&bin_boxes[bin]);
            n += bin_counts[bin];
            right_area[bin] = grown.half_area();
            right_count[bin] = n;
        }
        let mut grown = Aabb::EMPTY;
        let mut n = 0;
        for split in 1..BINS {
            grown.grow(&bin_boxes[split - 1]);
            n += bin_counts[split - 1];
            if n == 0 || right_count[split] == 0 {
                continue;
            }
            let cost = grown.half_area() * n as f64 + right_area[split] * right_count[split] as f64;
            if best.is_none_or(|(best_cost, _, _)| cost < best_cost) {
                best = Some((cost, axis, split));
            }
        }
    }
    let (cost, axis, split) = best?;
    let leaf_cost = bounds.half_area() * count as f64;
    if count <= MAX_LEAF && TRAVERSAL_COST * bounds.half_area() + cost >= leaf_cost {
        return None;
    }
    let low = centroid_bounds.min[axis];
    let scale = BINS as f64 / (centroid_bounds.max[axis] - low);
    let goes_left =
        |i: u32| ((((centroids[i as usize][axis] - low) * scale) as usize).min(BINS - 1)) < split;
    // In-place partition (the bins put at least one item on each side).
    let mut left = 0;
    for k in 0..count {
        if goes_left(items[k]) {
            items.swap(left, k);
            left += 1;
        }
    }
    (left > 0 && left < count).then_some(left)
}

/// Half the items on each side, split at the median centroid along the widest axis of
/// the centroids' box (any split, when they coincide).
fn median_split(items: &mut [u32], centroids: &[[f64; 3]], centroid_bounds: &Aabb) -> usize {
    let extent = [0, 1, 2].map(|axis| centroid_bounds.max[axis] - centroid_bounds.min[axis]);
    let axis = if extent[0] >= extent[1] && extent[0] >= extent[2] {
        0
    } else if extent[1] >= extent[2] {
        1
    } else {
        2
    };
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |&a, &b| {
        centroids[a as usize][axis].total_cmp(&centroids[b as usize][axis])
    });
    mid
}

/// Whether (t_min, t_max) can hold a t: t_min < t_max, neither NaN.
fn is_interval(t_min: f64, t_max: f64) -> bool {
    t_min < t_max
}

/// The parameter at which the ray enters `node`'s box within [t_min, t_max], or `None`.
#[inline]
fn enter(node: &Node, ray: &ShearedRay, t_min: f64, t_max: f64) -> Option<f64> {
    let mut near = t_min;
    let mut far = t_max;
    for axis in 0..3 {
        let a = (node.min[axis] - ray.origin[axis]) * ray.inverse_direction[axis];
        let b = (node.max[axis] - ray.origin[axis]) * ray.inverse_direction[axis];
        let (slab_near, slab_far) = if a <= b { (a, b) } else { (b, a) };
        // f64::max/min skip NaN (a non-finite ray), keeping the box: conservative.
        near = near.max(slab_near - slab_near.abs() * SLAB_ROUNDING);
        far = far.min(slab_far + slab_far.abs() * SLAB_ROUNDING);
    }
    (near <= far).then_some(near)
}

/// The closest hit as (index into the hierarchy's triangles, t, barycentrics); ties in t
/// go to the smallest (object, triangle).
pub(crate) fn closest(
    bvh: &SceneBvh,
    ray: &Ray,
    t_min: f64,
    t_max: f64,
) -> Option<(usize, f64, [f64; 2])> {
    if bvh.nodes.is_empty() || !is_interval(t_min, t_max) {
        return None;
    }
    let ray = ShearedRay::new(ray);
    let mut best: Option<(usize, f64, [f64; 2])> = None;
    let mut best_t = t_max;
    let key = |i: usize| (bvh.triangles[i].object, bvh.triangles[i].triangle);
    let mut stack = [0u32; STACK];
    let mut depth = 0;
    let mut node = 0usize;
    enter(&bvh.nodes[0], &ray, t_min, best_t)?;
    loop {
        let current = &bvh.nodes[node];
        if current.count > 0 {
            let first = current.first as usize;
            for i in first..first + current.count as usize {
                let Some((t, barycentrics)) =
                    ray.intersect(&bvh.triangles[i].vertices, t_min, t_max)
                else {
                    continue;
                };
                if !bvh.surface_present(&bvh.triangles[i], barycentrics) {
                    continue;
                }
                let better = match best {
                    None => true,
                    Some((j, t_best, _)) => t < t_best || (t == t_best && key(i) < key(j)),
                };
                if better {
                    best = Some((i, t, barycentrics));
                    best_t = t;
                }
            }
        } else {
            let left = current.first as usize;
            let near_left = enter(&bvh.nodes[left], &ray, t_min, best_t);
            let near_right = enter(&bvh.nodes[left + 1], &ray, t_min, best_t);
            match (near_left, near_right) {
                (Some(l), Some(r)) => {
                    let (first, second) = if l <= r {
                        (left, left + 1)
                    } else {
                        (left + 1, left)
                    };
                    if depth < STACK {
                        stack[depth] = second as u32;
                        depth += 1;
                    }
                    node = first;
                    continue;
                }
                (Some(_), None) => {
                    node = left;
                    continue;
                }
                (None, Some(_)) => {
                    node = left + 1;
                    continue;
                }
                (None, None) => {}
            }
        }
        // Next node from the stack, skipping those now beyond the best hit.
        loop {
            if depth == 0 {
                return best;
            }
            depth -= 1;
            node = stack[depth] as usize;
            if enter(&bvh.nodes[node], &ray, t_min, best_t).is_some() {
                break;
            }
        }
    }
}

/// Whether any triangle is hit with t_min < t < t_max.
pub(crate) fn any(bvh: &SceneBvh, ray: &Ray, t_min: f64, t_max: f64) -> bool {
    if bvh.nodes.is_empty() || !is_interval(t_min, t_max) {
        return false;
    }
    let ray = ShearedRay::new(ray);
    let mut stack = [0u32; STACK];
    stack[0] = 0;
    let mut depth = 1;
    while depth > 0 {
        depth -= 1;
        let node = &bvh.nodes[stack[depth] as usize];
        if enter(node, &ray, t_min, t_max).is_none() {
            continue;
        }
        if node.count > 0 {
            let first = node.first as usize;
            if bvh.triangles[first..first + node.count as usize]
                .iter()
                .any(|triangle| {
                    ray.intersect(&triangle.vertices, t_min, t_max)
                        .is_some_and(|(_, b)| bvh.surface_present(triangle, b))
                })
            {
                return true;
            }
        } else if depth + 2 <= STACK {
            stack[depth] = node.first + 1;
            stack[depth + 1] = node.first;
            depth += 2;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shape of the tree on a big built-in scene: depth within the traversal's
    /// stack, leaves within the heuristic's size, every triangle in exactly one leaf.
    #[test]
    fn the_tree_is_shallow_and_covers_every_triangle_once() {
        let scene = combustion_scene::builtin_scene("grid-7x7").unwrap();
        let bvh = SceneBvh::new(&scene);
        let mut covered = vec![0u8; bvh.triangles.len()];
        let (mut leaves, mut max_depth, mut largest_leaf) = (0, 0, 0);
        let mut cost = 0.0;
        let root_area = Aabb {
            min: bvh.nodes[0].min,
            max: bvh.nodes[0].max,
        }
        .half_area();
        let mut work = vec![(0usize, 1usize)];
        while let Some((index, depth)) = work.pop() {
            let node = bvh.nodes[index];
            max_depth = max_depth.max(depth);
            let area = Aabb {
                min: node.min,
                max: node.max,
            }
            .half_area()
                / root_area;
            if node.count > 0 {
                leaves += 1;
                largest_leaf = largest_leaf.max(node.count);
                cost += area * node.count as f64;
                for i in node.first..node.first + node.count {
                    covered[i as usize] += 1;
                }
            } else {
                cost += area * TRAVERSAL_COST;
                work.push((node.first as usize, depth + 1));
                work.push((node.first as usize + 1, depth + 1));
            }
        }
        println!(
            "grid-7x7: {} triangles, {} nodes, {leaves} leaves (largest {largest_leaf}), depth {max_depth}, SAH cost {cost:.1}",
            bvh.triangles.len(),
            bvh.nodes.len()
        );
        assert!(covered.iter().all(|&c| c == 1));
        assert!(max_depth < STACK);
        assert!(largest_leaf as usize <= MAX_LEAF);
    }
}
