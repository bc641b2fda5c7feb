//! Building the tree: primitives binned by the surface area heuristic into a binary tree (in
//! parallel for large inputs), then collapsed into eight-wide nodes.

use super::*;

/// A corner of a box with a number kept beside it, in the fourth lane that a `Vec3A` leaves
/// unused: how the build's primitives and binary nodes carry their indices in 32 bytes rather
/// than 48, in its two largest arrays.
#[derive(Debug, Clone, Copy)]
pub(super) struct Corner(Vec4);

impl Corner {
    pub(super) fn new(point: Vec3A, number: u32) -> Corner {
        Corner(point.extend(f32::from_bits(number)))
    }

    /// The corner, its fourth lane cleared: a number's bits read as a float are mostly a
    /// subnormal number, and arithmetic on those is slow even in a lane whose result is unused.
    #[inline(always)]
    pub(super) fn point(self) -> Vec3A {
        Vec3A::from_vec4(self.0.with_w(0.0))
    }

    #[inline(always)]
    pub(super) fn number(self) -> u32 {
        self.0.w.to_bits()
    }

    pub(super) fn set_number(&mut self, number: u32) {
        self.0.w = f32::from_bits(number);
    }
}

/// A binary node during the build: a leaf holds `first .. first + count` of the build order,
/// an inner node's children are `first` and `first + 1`; `first` is kept beside the box's
/// lower corner, `count` beside its upper one.
#[derive(Debug, Clone, Copy)]
pub(super) struct BinaryNode {
    min: Corner,
    max: Corner,
}

impl BinaryNode {
    pub(super) fn new(bounds: Aabb, first: u32, count: u32) -> BinaryNode {
        BinaryNode {
            min: Corner::new(bounds.min, first),
            max: Corner::new(bounds.max, count),
        }
    }

    #[inline(always)]
    pub(super) fn bounds(&self) -> Aabb {
        Aabb {
            min: self.min.point(),
            max: self.max.point(),
        }
    }

    #[inline(always)]
    pub(super) fn first(&self) -> u32 {
        self.min.number()
    }

    /// How many primitives a leaf holds; 0 for an inner node.
    #[inline(always)]
    pub(super) fn count(&self) -> u32 {
        self.max.number()
    }

    pub(super) fn set_range(&mut self, first: u32, count: u32) {
        self.min.set_number(first);
        self.max.set_number(count);
    }

    /// The node of a part whose nodes after its root now start at `rest_start`.
    pub(super) fn moved(&self, rest_start: usize) -> BinaryNode {
        let mut node = *self;
        if node.count() == 0 {
            node.set_range((rest_start + node.first() as usize - 1) as u32, 0);
        }
        node
    }

    /// A place held for a node laid out later.
    pub(super) const UNSET: BinaryNode = BinaryNode {
        min: Corner(Vec4::new(f32::INFINITY, f32::INFINITY, f32::INFINITY, 0.0)),
        max: Corner(Vec4::new(
            f32::NEG_INFINITY,
            f32::NEG_INFINITY,
            f32::NEG_INFINITY,
            0.0,
        )),
    };
}

/// Centroids are kept doubled (min + max): the same order, one multiplication fewer.
pub(super) fn centre(b: &Aabb) -> Vec3A {
    b.min + b.max
}

/// A primitive as the build sorts it: its box, with its index in the input kept beside the
/// lower corner.
#[derive(Debug, Clone, Copy)]
pub(super) struct Prim {
    min: Corner,
    max: Vec3A,
}

impl Prim {
    pub(super) fn new(bounds: Aabb, index: u32) -> Prim {
        Prim {
            min: Corner::new(bounds.min, index),
            max: bounds.max,
        }
    }

    #[inline(always)]
    pub(super) fn bounds(&self) -> Aabb {
        Aabb {
            min: self.min.point(),
            max: self.max,
        }
    }

    /// The primitive's index in the input.
    #[inline(always)]
    pub(super) fn index(&self) -> u32 {
        self.min.number()
    }
}

/// The boxes of a range of primitives and of their (doubled) centroids.
#[derive(Debug, Clone, Copy)]
pub(super) struct Extent {
    bounds: Aabb,
    centres: Aabb,
}

impl Extent {
    pub(super) const EMPTY: Extent = Extent {
        bounds: Aabb::EMPTY,
        centres: Aabb::EMPTY,
    };

    pub(super) fn of(prims: &[Prim]) -> Extent {
        prims.iter().fold(Extent::EMPTY, |e, p| {
            let b = p.bounds();
            Extent {
                bounds: e.bounds.union(b),
                centres: e.centres.grow(centre(&b)),
            }
        })
    }

    /// [`Extent::of`] on rayon's threads, for the whole input: the same boxes in any grouping.
    pub(super) fn of_all(prims: &[Prim]) -> Extent {
        prims.par_chunks(PARALLEL_MIN).map(Extent::of).reduce(
            || Extent::EMPTY,
            |a, b| Extent {
                bounds: a.bounds.union(b.bounds),
                centres: a.centres.union(b.centres),
            },
        )
    }
}

/// Binary binned-SAH build; `prims` ends in leaf order. Node 0 is the root; an inner node's
/// children are `first` and `first + 1`. The top of the tree is built in parallel on rayon's
/// threads; the tree is the same whatever the number of threads.
pub(super) fn build_binary(prims: &mut [Prim], leaf: LeafSize) -> Vec<BinaryNode> {
    let root = Extent::of_all(prims);
    // On one thread the parts would be built one after another all the same: the tree is
    // built as one part, in its own array, with no second array to lay parts out in (a
    // megabyte of fresh pages for a 100k-triangle mesh, at the peak of a one-thread run).
    if rayon::current_num_threads() == 1 {
        return build_sequential(prims, root, 0, 0, leaf);
    }
    let built = build_subtree(prims, root, 0, 0, leaf);
    // The parts built apart are laid out once, in one array made at its size: merged level by
    // level, every level was a copy of the nodes below it into fresh pages.
    let mut nodes = Vec::with_capacity(built.len());
    nodes.push(BinaryNode::UNSET);
    built.lay_out(&mut nodes, 0);
    nodes
}

/// Subtrees at least this large are split off to be built in parallel.
pub(super) const PARALLEL_MIN: usize = 8192;

/// A subtree as built: one part built alone, or a node whose two sides were built in parallel.
pub(super) enum Built {
    /// Its root at 0, each inner node's children at `first` and `first + 1` of this array.
    Alone(Vec<BinaryNode>),
    Split {
        bounds: Aabb,
        sides: Box<[Built; 2]>,
    },
}

impl Built {
    /// How many nodes it has.
    pub(super) fn len(&self) -> usize {
        match self {
            Built::Alone(nodes) => nodes.len(),
            Built::Split { sides, .. } => 1 + sides[0].len() + sides[1].len(),
        }
    }

    /// Puts the root at `nodes[root]` (already there, to be filled) and the rest at the end of
    /// `nodes`: a node, then its two children side by side, then the rest of each side.
    pub(super) fn lay_out(self, nodes: &mut Vec<BinaryNode>, root: usize) {
        match self {
            Built::Alone(part) => {
                // Node i > 0 of the part goes to rest_start + i - 1.
                let rest_start = nodes.len();
                nodes[root] = part[0].moved(rest_start);
                nodes.extend(part[1..].iter().map(|node| node.moved(rest_start)));
            }
            Built::Split { bounds, sides } => {
                let first = nodes.len();
                nodes[root] = BinaryNode::new(bounds, first as u32, 0);
                nodes.extend([BinaryNode::UNSET; 2]);
                let [left, right] = *sides;
                left.lay_out(nodes, first);
                right.lay_out(nodes, first + 1);
            }
        }
    }
}

/// The subtree over `prims` (which start at `offset` in the whole build order).
pub(super) fn build_subtree(
    prims: &mut [Prim],
    extent: Extent,
    depth: usize,
    offset: usize,
    leaf: LeafSize,
) -> Built {
    if prims.len() < PARALLEL_MIN || depth >= MAX_SAH_DEPTH {
        return Built::Alone(build_sequential(prims, extent, depth, offset, leaf));
    }
    let Some((mid, left, right)) = split(prims, extent, depth, leaf) else {
        return Built::Alone(build_sequential(prims, extent, depth, offset, leaf));
    };
    let (left_prims, right_prims) = prims.split_at_mut(mid);
    let sides = rayon::join(
        || build_subtree(left_prims, left, depth + 1, offset, leaf),
        || build_subtree(right_prims, right, depth + 1, offset + mid, leaf),
    );
    Built::Split {
        bounds: extent.bounds,
        sides: Box::new(sides.into()),
    }
}

/// How a node is divided: the size of the left part and the extents of both parts, with `items`
/// partitioned in place; `None` for a leaf.
pub(super) fn split(
    items: &mut [Prim],
    extent: Extent,
    depth: usize,
    leaf: LeafSize,
) -> Option<(usize, Extent, Extent)> {
    let count = items.len() as u32;
    let sah = if depth < MAX_SAH_DEPTH && count > leaf.min_split {
        sah_split(items, extent.bounds, extent.centres, leaf)
    } else {
        None
    };
    match sah {
        Some(split) => Some(split),
        None if count <= leaf.max => None,
        None => {
            // All centroids in one spot, or too deep: halve by count along the widest axis.
            let centres = extent.centres;
            let axis = (centres.max - centres.min).max_position();
            let half = items.len() / 2;
            items.select_nth_unstable_by(half, |a, b| {
                centre(&a.bounds())[axis].total_cmp(&centre(&b.bounds())[axis])
            });
            Some((half, Extent::of(&items[..half]), Extent::of(&items[half..])))
        }
    }
}

pub(super) fn build_sequential(
    prims: &mut [Prim],
    extent: Extent,
    depth: usize,
    offset: usize,
    leaf: LeafSize,
) -> Vec<BinaryNode> {
    let mut nodes = Vec::with_capacity(prims.len() / 2 + 1);
    nodes.push(BinaryNode::new(extent.bounds, 0, 0));
    let mut pending = vec![(0usize, 0usize, prims.len(), depth, extent.centres)];
    while let Some((index, start, end, depth, centres)) = pending.pop() {
        let extent = Extent {
            bounds: nodes[index].bounds(),
            centres,
        };
        let Some((mid, left, right)) = split(&mut prims[start..end], extent, depth, leaf) else {
            nodes[index].set_range((offset + start) as u32, (end - start) as u32);
            continue;
        };
        let first = nodes.len();
        nodes[index].set_range(first as u32, 0);
        for side in [left, right] {
            nodes.push(BinaryNode::new(side.bounds, 0, 0));
        }
        pending.push((first + 1, start + mid, end, depth + 1, right.centres));
        pending.push((first, start, start + mid, depth + 1, left.centres));
    }
    nodes
}

/// The best binned-SAH split of `items`, partitioned in place: the size of the left part and
/// the extents of both parts; or `None` when keeping a leaf is cheaper (or no split separates
/// anything).
///
/// One function, long: binning, the sweep over the bins and the partition share the bins and
/// bounds, and this is the build's inner loop (every node of every mesh), measured in
/// performance.md; split, each part would hand its arrays to the next.
pub(super) fn sah_split(
    items: &mut [Prim],
    bounds: Aabb,
    centres: Aabb,
    leaf: LeafSize,
) -> Option<(usize, Extent, Extent)> {
    let count = items.len();
    let (lo, extent) = (centres.min, centres.max - centres.min);
    let scale = Vec3A::splat(BINS as f32) / extent;
    // Bin k takes the centroids that round to k. The rounding is done by adding 2^23, which
    // leaves the integer in the low bits of the float: a saturating `as` cast, three per
    // primitive and level, was a fifth of the whole build.
    let top = Vec3A::splat((BINS - 1) as f32);
    pub(super) const ROUND: f32 = (1 << 23) as f32;
    let bins_of = |c: Vec3A| -> [usize; 3] {
        let b = ((c - lo) * scale).clamp(Vec3A::ZERO, top) + ROUND;
        [b.x, b.y, b.z].map(|x| (x.to_bits() & 0xFF) as usize)
    };
    let bin_on = |c: Vec3A, axis: usize| -> usize {
        let b = ((c[axis] - lo[axis]) * scale[axis]).clamp(0.0, top.x) + ROUND;
        (b.to_bits() & 0xFF) as usize
    };
    // Small nodes are binned along their widest axis only: near the leaves a split along another
    // axis rarely wins, and the bottom levels hold most of the nodes.
    let widest = extent.max_position();
    let binnable = |axis: usize| extent[axis].partial_cmp(&0.0) == Some(Ordering::Greater);
    // (cost, axis, boundary, left box, right box)
    let mut best: Option<(f32, usize, usize, Aabb, Aabb)> = None;
    let mut consider = |axis: usize, bins: &Bins| {
        if let Some((cost, k, left, right)) = bins.best_boundary(count)
            && best.is_none_or(|best| cost < best.0)
        {
            best = Some((cost, axis, k, left, right));
        }
    };
    if count >= SMALL_NODE {
        let bin_all = |mut bins: [Bins; 3], items: &[Prim]| {
            for p in items {
                let b = p.bounds();
                let bin = bins_of(centre(&b));
                for (axis, axis_bins) in bins.iter_mut().enumerate() {
                    axis_bins.add(bin[axis], &b);
                }
            }
            bins
        };
        // The top nodes hold most of the primitives and are split before their subtrees can be
        // built in parallel, so their binning is shared out; unions and counts give the same
        // bins in any grouping.
        let bins = if count >= PARALLEL_MIN {
            items
                .par_chunks(PARALLEL_MIN / 2)
                .fold(|| [Bins::EMPTY; 3], bin_all)
                .reduce(
                    || [Bins::EMPTY; 3],
                    |a, b| [0, 1, 2].map(|axis| a[axis].merge(&b[axis])),
                )
        } else {
            bin_all([Bins::EMPTY; 3], items)
        };
        for (axis, axis_bins) in bins.iter().enumerate() {
            if binnable(axis) {
                consider(axis, axis_bins);
            }
        }
    } else if binnable(widest) {
        let mut bins = Bins::EMPTY;
        for p in items.iter() {
            let b = p.bounds();
            bins.add(bin_on(centre(&b), widest), &b);
        }
        consider(widest, &bins);
    }
    let (cost, axis, boundary, left_bounds, right_bounds) = best?;
    let split_cost = TRAVERSAL_COST + cost / bounds.half_area().max(f32::MIN_POSITIVE);
    if split_cost >= count as f32 && count as u32 <= leaf.max {
        return None;
    }
    let (mut left_centres, mut right_centres) = (Aabb::EMPTY, Aabb::EMPTY);
    let mut left = 0;
    // Without branches: which side a primitive falls on is a coin toss to the branch predictor,
    // and its misses were half the build's time. The same moves as the branching loop (a swap of
    // an item with itself moves nothing), so the same order and the same tree.
    for i in 0..count {
        let c = centre(&items[i].bounds());
        let goes_left = bin_on(c, axis) < boundary;
        let mask = BVec3A::splat(goes_left);
        left_centres = Aabb {
            min: Vec3A::select(mask, left_centres.min.min(c), left_centres.min),
            max: Vec3A::select(mask, left_centres.max.max(c), left_centres.max),
        };
        right_centres = Aabb {
            min: Vec3A::select(mask, right_centres.min, right_centres.min.min(c)),
            max: Vec3A::select(mask, right_centres.max, right_centres.max.max(c)),
        };
        items.swap(i, if goes_left { left } else { i });
        left += usize::from(goes_left);
    }
    let side = |bounds, centres| Extent { bounds, centres };
    Some((
        left,
        side(left_bounds, left_centres),
        side(right_bounds, right_centres),
    ))
}

/// The boxes and counts of one axis's bins.
#[derive(Clone, Copy)]
pub(super) struct Bins {
    boxes: [Aabb; BINS],
    counts: [u32; BINS],
}

impl Bins {
    pub(super) const EMPTY: Bins = Bins {
        boxes: [Aabb::EMPTY; BINS],
        counts: [0; BINS],
    };

    /// The bins of both `self`'s primitives and `other`'s.
    pub(super) fn merge(&self, other: &Bins) -> Bins {
        let mut merged = *self;
        for k in 0..BINS {
            merged.boxes[k] = merged.boxes[k].union(other.boxes[k]);
            merged.counts[k] += other.counts[k];
        }
        merged
    }

    #[inline(always)]
    pub(super) fn add(&mut self, bin: usize, b: &Aabb) {
        self.boxes[bin] = self.boxes[bin].union(*b);
        self.counts[bin] += 1;
    }

    /// The cheapest boundary between bins by the SAH: its cost (areas times counts, not yet
    /// divided by the parent's area), the first bin on its right, and both sides' boxes.
    pub(super) fn best_boundary(&self, count: usize) -> Option<(f32, usize, Aabb, Aabb)> {
        // The right side of each boundary, swept from the right. Entries whose right side is
        // empty are never read: their left side holds everything, which is no split.
        let mut right_boxes = [Aabb::EMPTY; BINS];
        let mut right_costs = [0.0f32; BINS];
        let (mut b, mut n) = (Aabb::EMPTY, 0u32);
        for k in (1..BINS).rev() {
            b = b.union(self.boxes[k]);
            n += self.counts[k];
            if n > 0 {
                right_boxes[k] = b;
                right_costs[k] = b.half_area_unchecked() * n as f32;
            }
        }
        let mut best: Option<(f32, usize, Aabb, Aabb)> = None;
        let (mut b, mut n) = (Aabb::EMPTY, 0u32);
        for k in 1..BINS {
            b = b.union(self.boxes[k - 1]);
            n += self.counts[k - 1];
            if n == 0 || n as usize == count {
                continue;
            }
            let cost = b.half_area_unchecked() * n as f32 + right_costs[k];
            if best.is_none_or(|best| cost < best.0) {
                best = Some((cost, k, b, right_boxes[k]));
            }
        }
        best
    }
}

/// Eight-wide nodes from the binary tree: each takes its binary node's children and keeps
/// opening the largest inner one among them until it has eight.
pub(super) fn collapse(binary: &[BinaryNode]) -> Vec<Node> {
    // No more wide nodes than binary inner nodes: room made once (what is not used is never
    // touched), not grown by doubling into fresh pages.
    let mut nodes = Vec::with_capacity(binary.len() / 2 + 1);
    nodes.push(Node::EMPTY);
    // (binary node, wide node to fill)
    let mut pending = vec![(0usize, 0usize)];
    while let Some((source, target)) = pending.pop() {
        let root = binary[source];
        let mut children: Vec<usize> = if root.count() > 0 {
            vec![source]
        } else {
            vec![root.first() as usize, root.first() as usize + 1]
        };
        while children.len() < WIDTH {
            let widest = children
                .iter()
                .enumerate()
                .filter(|&(_, &c)| binary[c].count() == 0)
                .max_by(|a, b| {
                    binary[*a.1]
                        .bounds()
                        .half_area()
                        .total_cmp(&binary[*b.1].bounds().half_area())
                });
            let Some((slot, &open)) = widest else { break };
            let first = binary[open].first() as usize;
            children[slot] = first;
            children.push(first + 1);
        }
        for (lane, &c) in children.iter().enumerate() {
            let child = binary[c];
            if child.count() > 0 {
                let count = child.count() as u8;
                nodes[target].set_lane(lane, padded(child.bounds()), child.first(), count);
            } else {
                let index = nodes.len();
                nodes.push(Node::EMPTY);
                nodes[target].set_lane(lane, padded(child.bounds()), index as u32, 0);
                pending.push((c, index));
            }
        }
    }
    nodes
}

/// A box grown by a few ulps of its coordinates, so that rounding in the slab test never loses
/// a hit on its surface (a ray through a triangle's edge on the box's face, say).
pub(super) fn padded(b: Aabb) -> Aabb {
    let pad =
        (b.min.abs().max(b.max.abs()) * (4.0 * f32::EPSILON)).max(Vec3A::splat(f32::MIN_POSITIVE));
    Aabb {
        min: b.min - pad,
        max: b.max + pad,
    }
}
