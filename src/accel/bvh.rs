//! A binary bounding volume hierarchy over boxes: binned SAH build, 32-byte nodes, closest-hit
//! traversal that visits the nearer child first and shrinks t_max as it finds hits.
//!
//! The tree knows only boxes; what sits in a leaf is the caller's business, tested through a
//! closure, so triangles, spheres and whole instances all use the same code, monomorphised.

use glam::{Vec3, Vec3A};

use crate::geometry::{Aabb, Ray};

/// 32 bytes, two to a cache line. Interior nodes have `count == 0` and their children at
/// `first` and `first + 1`; leaves hold the primitives `first .. first + count`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C)]
pub struct Node {
    min: Vec3,
    first: u32,
    max: Vec3,
    count: u32,
}

const _: () = assert!(std::mem::size_of::<Node>() == 32);

impl Node {
    fn bounds(&self) -> Aabb {
        Aabb {
            min: self.min.into(),
            max: self.max.into(),
        }
    }

    fn set_bounds(&mut self, b: Aabb) {
        self.min = b.min.into();
        self.max = b.max.into();
    }
}

#[derive(Debug, Clone, Default, PartialEq)]
pub struct Bvh {
    nodes: Vec<Node>,
}

const BINS: usize = 16;
/// Leaves never grow past this, whatever the SAH says.
const MAX_LEAF: u32 = 8;
/// Beyond this depth splits are by count, which bounds the depth (and the traversal stack).
const MAX_SAH_DEPTH: usize = 64;
const STACK: usize = MAX_SAH_DEPTH + 40;
/// The cost of a node visit relative to one primitive test.
const TRAVERSAL_COST: f32 = 1.0;

impl Bvh {
    /// Builds over the given primitive boxes. Returns the tree and the order the primitives must
    /// be stored in for it: leaf ranges index that order, `order[i]` is the input index.
    pub fn build(boxes: &[Aabb]) -> (Bvh, Vec<u32>) {
        let mut order: Vec<u32> = (0..boxes.len() as u32).collect();
        let centroids: Vec<Vec3A> = boxes.iter().map(Aabb::centroid).collect();
        if boxes.is_empty() {
            return (Bvh::default(), order);
        }
        let mut nodes = Vec::with_capacity(2 * boxes.len());
        nodes.push(Node {
            min: Vec3::ZERO,
            first: 0,
            max: Vec3::ZERO,
            count: boxes.len() as u32,
        });
        let mut pending = vec![(0usize, 0usize, boxes.len(), 0usize)];
        while let Some((index, start, end, depth)) = pending.pop() {
            let items = &mut order[start..end];
            let mut bounds = Aabb::EMPTY;
            let mut centre_bounds = Aabb::EMPTY;
            for &i in items.iter() {
                bounds = bounds.union(boxes[i as usize]);
                centre_bounds = centre_bounds.grow(centroids[i as usize]);
            }
            nodes[index].set_bounds(bounds);
            let count = items.len() as u32;
            let split = if depth < MAX_SAH_DEPTH {
                sah_split(items, boxes, &centroids, bounds, centre_bounds)
            } else {
                None
            };
            let mid = match split {
                Some(mid) => mid,
                None if count <= MAX_LEAF => {
                    nodes[index].first = start as u32;
                    nodes[index].count = count;
                    continue;
                }
                None => {
                    // All centroids in one spot, or too deep: halve by count along the widest axis.
                    let axis = (centre_bounds.max - centre_bounds.min).max_position();
                    let half = items.len() / 2;
                    items.select_nth_unstable_by(half, |&a, &b| {
                        centroids[a as usize][axis].total_cmp(&centroids[b as usize][axis])
                    });
                    half
                }
            };
            let left = nodes.len();
            nodes[index].first = left as u32;
            nodes[index].count = 0;
            nodes.push(Node {
                min: Vec3::ZERO,
                first: 0,
                max: Vec3::ZERO,
                count: 0,
            });
            nodes.push(nodes[left]);
            pending.push((left + 1, start + mid, end, depth + 1));
            pending.push((left, start, start + mid, depth + 1));
        }
        (Bvh { nodes }, order)
    }

    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, Node::bounds)
    }

    pub fn size_in_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>()
    }

    /// Closest-hit traversal. `hit(i, t_max)` tests primitive `i` (in build order) and returns
    /// its t if it is nearer than `t_max`. Returns the final t_max.
    #[inline(always)]
    pub fn traverse(
        &self,
        ray: &Ray,
        t_min: f32,
        mut t_max: f32,
        mut hit: impl FnMut(u32, f32) -> Option<f32>,
    ) -> f32 {
        let nodes = &self.nodes[..];
        match nodes.first() {
            Some(root) if root.bounds().hit(ray, t_min, t_max).is_some() => {}
            _ => return t_max,
        }
        let mut stack = [(0u32, 0f32); STACK];
        let mut top = 0;
        let mut node = &nodes[0];
        loop {
            if node.count > 0 {
                for i in node.first..node.first + node.count {
                    if let Some(t) = hit(i, t_max) {
                        t_max = t;
                    }
                }
            } else {
                let left = &nodes[node.first as usize];
                let right = &nodes[node.first as usize + 1];
                let near_left = left.bounds().hit(ray, t_min, t_max);
                let near_right = right.bounds().hit(ray, t_min, t_max);
                match (near_left, near_right) {
                    (Some(l), Some(r)) => {
                        let (near, far, far_t) = if l <= r {
                            (left, node.first + 1, r)
                        } else {
                            (right, node.first, l)
                        };
                        stack[top] = (far, far_t);
                        top += 1;
                        node = near;
                        continue;
                    }
                    (Some(_), None) => {
                        node = left;
                        continue;
                    }
                    (None, Some(_)) => {
                        node = right;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            // Take the nearest postponed node that a hit found since has not ruled out.
            loop {
                if top == 0 {
                    return t_max;
                }
                top -= 1;
                let (index, entry) = stack[top];
                if entry <= t_max {
                    node = &nodes[index as usize];
                    break;
                }
            }
        }
    }
}

/// The best binned-SAH split of `items`, partitioned in place; returns the size of the left
/// part, or `None` when keeping a leaf is cheaper (or no split separates anything).
fn sah_split(
    items: &mut [u32],
    boxes: &[Aabb],
    centroids: &[Vec3A],
    bounds: Aabb,
    centre_bounds: Aabb,
) -> Option<usize> {
    let count = items.len();
    if count <= 2 {
        return None;
    }
    let extent = centre_bounds.max - centre_bounds.min;
    let scale = Vec3A::splat(BINS as f32) / extent;
    let bin_of = |c: Vec3A, axis: usize| -> usize {
        (((c[axis] - centre_bounds.min[axis]) * scale[axis]) as usize).min(BINS - 1)
    };
    let mut bins = [[(Aabb::EMPTY, 0u32); BINS]; 3];
    for &i in items.iter() {
        let c = centroids[i as usize];
        for (axis, axis_bins) in bins.iter_mut().enumerate() {
            if extent[axis] > 0.0 {
                let bin = &mut axis_bins[bin_of(c, axis)];
                bin.0 = bin.0.union(boxes[i as usize]);
                bin.1 += 1;
            }
        }
    }
    let mut best: Option<(f32, usize, usize)> = None;
    for (axis, axis_bins) in bins.iter().enumerate() {
        if extent[axis] <= 0.0 {
            continue;
        }
        // Cost of the right side of each boundary, swept from the right.
        let mut right_cost = [0.0f32; BINS];
        let (mut b, mut n) = (Aabb::EMPTY, 0u32);
        for k in (1..BINS).rev() {
            b = b.union(axis_bins[k].0);
            n += axis_bins[k].1;
            right_cost[k] = b.half_area() * n as f32;
        }
        let (mut b, mut n) = (Aabb::EMPTY, 0u32);
        for k in 1..BINS {
            b = b.union(axis_bins[k - 1].0);
            n += axis_bins[k - 1].1;
            if n == 0 || n as usize == count {
                continue;
            }
            let cost = b.half_area() * n as f32 + right_cost[k];
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, k));
            }
        }
    }
    let (cost, axis, boundary) = best?;
    let split_cost = TRAVERSAL_COST + cost / bounds.half_area().max(f32::MIN_POSITIVE);
    if split_cost >= count as f32 && count as u32 <= MAX_LEAF {
        return None;
    }
    // Partition: items whose centroid falls left of the boundary first.
    let mut left = 0;
    for i in 0..count {
        if bin_of(centroids[items[i] as usize], axis) < boundary {
            items.swap(i, left);
            left += 1;
        }
    }
    Some(left)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box_at(x: f32, y: f32, z: f32) -> Aabb {
        let c = Vec3A::new(x, y, z);
        Aabb {
            min: c - 0.25,
            max: c + 0.25,
        }
    }

    /// Every primitive is in exactly one leaf, and every node's box holds its children's.
    fn check_structure(bvh: &Bvh, order: &[u32], boxes: &[Aabb]) {
        let mut seen = vec![0; boxes.len()];
        let mut pending = vec![0usize];
        while let Some(i) = pending.pop() {
            let node = bvh.nodes[i];
            let b = node.bounds();
            if node.count > 0 {
                for k in node.first..node.first + node.count {
                    let prim = order[k as usize] as usize;
                    seen[prim] += 1;
                    assert_eq!(b.union(boxes[prim]), b);
                }
            } else {
                for child in [node.first as usize, node.first as usize + 1] {
                    assert_eq!(b.union(bvh.nodes[child].bounds()), b);
                    pending.push(child);
                }
            }
        }
        assert!(seen.iter().all(|&n| n == 1));
    }

    #[test]
    fn every_primitive_lands_in_one_leaf() {
        let boxes: Vec<Aabb> = (0..1000)
            .map(|i| unit_box_at((i % 10) as f32, (i / 10 % 10) as f32, (i / 100) as f32))
            .collect();
        let (bvh, order) = Bvh::build(&boxes);
        check_structure(&bvh, &order, &boxes);
        assert!(bvh.node_count() > 100);
    }

    #[test]
    fn identical_boxes_still_split_into_small_leaves() {
        let boxes = vec![unit_box_at(1.0, 2.0, 3.0); 100];
        let (bvh, order) = Bvh::build(&boxes);
        check_structure(&bvh, &order, &boxes);
        assert!(bvh.nodes.iter().all(|n| n.count <= MAX_LEAF));
    }

    #[test]
    fn traversal_finds_the_closest_box_hit() {
        let boxes: Vec<Aabb> = (0..50).map(|i| unit_box_at(0.0, 0.0, i as f32)).collect();
        let (bvh, order) = Bvh::build(&boxes);
        let ray = Ray::new(Vec3A::new(0.0, 0.0, 100.0), -Vec3A::Z);
        let mut closest = None;
        let t = bvh.traverse(&ray, 0.0, f32::INFINITY, |i, t_max| {
            let prim = order[i as usize];
            let t = boxes[prim as usize].hit(&ray, 0.0, t_max)?;
            closest = Some(prim);
            Some(t)
        });
        assert_eq!(closest, Some(49));
        assert_eq!(t, 100.0 - 49.25);
    }

    #[test]
    fn an_empty_tree_is_never_entered() {
        let (bvh, _) = Bvh::build(&[]);
        let ray = Ray::new(Vec3A::ZERO, Vec3A::Z);
        let t = bvh.traverse(&ray, f32::NEG_INFINITY, f32::INFINITY, |_, _| unreachable!());
        assert_eq!(t, f32::INFINITY);
    }
}
