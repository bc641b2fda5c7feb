//! The course's uniform grid (assignments 5 and 6): the scene's box cut into nx × ny × nz
//! cells, each listing the primitives whose box reaches into it, and the 3D-DDA walk that visits
//! the cells a ray crosses, in order.
//!
//! raycast's BVH stays the default; the grid is there for the course's images, statistics and
//! lessons, and it gives the same hits.

use std::ops::ControlFlow;

use glam::{UVec3, Vec3A};

use crate::geometry::{Aabb, Ray};

/// The most cells a grid may have: 2^26, 256 MiB of cell offsets.
pub const MAX_CELLS: u64 = 1 << 26;
/// The most (cell, primitive) entries a grid may hold: 2^28, 2 GiB.
pub const MAX_ENTRIES: u64 = 1 << 28;

/// One primitive as the grid lists it: an item of the world, and for a mesh, its triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Primitive {
    /// Index into the world's items, in their stored order.
    pub item: u32,
    /// The triangle's index in the item's mesh; 0 for a sphere.
    pub triangle: u32,
}

/// Where a primitive reaches, for filling the cells.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Extent {
    /// Every cell the box overlaps.
    Box(Aabb),
    /// The handout's tighter test for a sphere: every cell whose centre is within the radius
    /// plus half the cell's diagonal of the sphere's centre (no cell the sphere touches is
    /// missed).
    Sphere {
        /// In world space.
        center: Vec3A,
        /// In world units.
        radius: f32,
    },
    /// A student's sphere: every cell whose centre lies inside it (the handout's test without
    /// its margin: a cell the sphere passes through but does not hold the centre of is
    /// missed).
    SphereByCentres {
        /// In world space.
        center: Vec3A,
        /// In world units.
        radius: f32,
    },
    /// A student's box: on each axis, the cells from its lowest corner's up to, and not
    /// including, its highest corner's (a loop bound written with `<`).
    BoxShortOfItsEnd(Aabb),
}

impl Extent {
    /// The box around every cell the extent can list.
    pub fn reach(&self) -> Aabb {
        match *self {
            Extent::Box(b) | Extent::BoxShortOfItsEnd(b) => b,
            Extent::Sphere { center, radius } | Extent::SphereByCentres { center, radius } => {
                Aabb {
                    min: center - radius,
                    max: center + radius,
                }
            }
        }
    }
}

/// A grid that cannot be built.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum GridError {
    /// More cells than [`MAX_CELLS`]: the number asked for.
    TooManyCells(u64),
    /// More (cell, primitive) entries than [`MAX_ENTRIES`]: the count when the build gave up
    /// (the whole grid would list at least that many).
    TooManyEntries(u64),
}

impl std::fmt::Display for GridError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GridError::TooManyCells(n) => {
                write!(f, "a grid of {n} cells is too large: at most {MAX_CELLS}")
            }
            GridError::TooManyEntries(n) => write!(
                f,
                "the grid would list {n} primitives in its cells, more than the {MAX_ENTRIES} \
                 that fit in memory; use fewer cells"
            ),
        }
    }
}

/// The scene's box cut into nx × ny × nz equal cells, each listing the primitives that reach
/// into it, in one flat array (compressed sparse rows).
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// The cells' box: the scene's, with flat sides given some thickness.
    bounds: Aabb,
    cells: UVec3,
    cell_size: Vec3A,
    /// Cell c lists `entries[starts[c]..starts[c + 1]]`; cells are numbered x fastest.
    starts: Vec<u32>,
    entries: Vec<Primitive>,
}

/// How a grid's march sets up its steps along an axis the ray runs down (the way it steps
/// along an axis it runs up is the same in each).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum March {
    /// The handout's: the first crossing at the cell's lower face, each step's t positive.
    Course,
    /// The first crossing taken at the cell's upper face, as for an axis the ray runs up.
    UpperFaceFirst,
    /// Each step's t left as size / d, without its absolute value: negative.
    SignedStep,
}

/// A cell the walk has reached.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cell<'a> {
    /// Which cell: its place on each axis, counted from the grid's lowest corner.
    pub index: UVec3,
    /// What the cell lists, in the order the primitives were given to [`Grid::build`].
    pub primitives: &'a [Primitive],
    /// The ray's t where it enters the cell (clipped to the walk's range).
    pub t_enter: f32,
    /// The ray's t where it leaves the cell (clipped to the walk's range).
    pub t_exit: f32,
    /// The axis (0 to 2 for x to z) of the face the ray came in through; for the first cell,
    /// the face the ray would have entered by.
    pub entered_axis: usize,
    /// The sign, -1 or 1, of that face's outward normal on its axis.
    pub entered_sign: f32,
}

impl Grid {
    /// Cuts `bounds` into `cells` and lists each primitive in every cell it reaches.
    ///
    /// One function: the two passes (count, then fill the CSR lists) must visit the cells in
    /// the same order, which is easiest to see side by side.
    pub fn build(
        bounds: Aabb,
        cells: UVec3,
        primitives: &[(Primitive, Extent)],
    ) -> Result<Grid, GridError> {
        let count = u64::from(cells.x) * u64::from(cells.y) * u64::from(cells.z);
        if count > MAX_CELLS {
            return Err(GridError::TooManyCells(count));
        }
        // A flat scene (every triangle in one plane) still gets cells of some thickness.
        let extent = if bounds.is_empty() {
            Vec3A::ZERO
        } else {
            bounds.max - bounds.min
        };
        let pad = (extent.max_element() * 1e-4).max(1e-4);
        let thin = extent.cmplt(Vec3A::splat(pad));
        let bounds = if bounds.is_empty() {
            Aabb {
                min: Vec3A::splat(-pad),
                max: Vec3A::splat(pad),
            }
        } else {
            Aabb {
                min: Vec3A::select(thin, bounds.min - pad, bounds.min),
                max: Vec3A::select(thin, bounds.max + pad, bounds.max),
            }
        };
        let cell_size = (bounds.max - bounds.min) / cells.as_vec3a();
        let mut grid = Grid {
            bounds,
            cells,
            cell_size,
            starts: vec![0; count as usize + 1],
            entries: Vec::new(),
        };
        // Boxes are widened a little, so that a hit point rounded just outside a primitive's
        // box still finds the primitive listed in its cell.
        let margin = extent.max_element() * 1e-5;
        // Two passes: count each cell's entries, then fill them in place.
        let mut counts = vec![0u32; count as usize];
        let mut total: u64 = 0;
        for (_, extent) in primitives {
            grid.for_each_cell(extent, margin, |cell| {
                counts[cell] += 1;
                total += 1;
            });
            if total > MAX_ENTRIES {
                return Err(GridError::TooManyEntries(total));
            }
        }
        let mut start = 0;
        for (c, n) in counts.iter().enumerate() {
            grid.starts[c] = start;
            start += n;
        }
        grid.starts[count as usize] = start;
        grid.entries = vec![
            Primitive {
                item: 0,
                triangle: 0
            };
            start as usize
        ];
        let mut next = grid.starts.clone();
        for &(primitive, extent) in primitives {
            let (entries, next) = (&mut grid.entries, &mut next);
            grid_fill(
                &grid.bounds,
                grid.cells,
                grid.cell_size,
                &extent,
                margin,
                |cell| {
                    entries[next[cell] as usize] = primitive;
                    next[cell] += 1;
                },
            );
        }
        Ok(grid)
    }

    /// The cells' box: the scene's, with flat sides given some thickness.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// How many cells the grid has along x, y and z.
    pub fn cells(&self) -> UVec3 {
        self.cells
    }

    /// How many primitives cell `index` lists.
    pub fn count(&self, index: UVec3) -> u32 {
        let c = self.cell_number(index);
        self.starts[c + 1] - self.starts[c]
    }

    /// Cells holding at least one primitive, and (cell, primitive) entries in all.
    pub fn occupancy(&self) -> (usize, usize) {
        let occupied = self.starts.windows(2).filter(|w| w[1] > w[0]).count();
        (occupied, self.entries.len())
    }

    fn cell_number(&self, index: UVec3) -> usize {
        (index.x + self.cells.x * (index.y + self.cells.y * index.z)) as usize
    }

    fn for_each_cell(&self, extent: &Extent, margin: f32, f: impl FnMut(usize)) {
        grid_fill(&self.bounds, self.cells, self.cell_size, extent, margin, f);
    }

    /// The primitives cell `index` lists (`index` within [`Grid::cells`]: one outside the grid
    /// panics).
    #[inline]
    pub fn primitives(&self, index: UVec3) -> &[Primitive] {
        let c = self.cell_number(index);
        &self.entries[self.starts[c] as usize..self.starts[c + 1] as usize]
    }

    /// Walks the cells `ray` crosses with t in [t_min, t_max], nearest first (3D-DDA), until
    /// `visit` breaks or the ray leaves the grid.
    #[inline]
    pub fn walk<'a>(
        &'a self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        visit: impl FnMut(Cell<'a>) -> ControlFlow<()>,
    ) {
        self.walk_marching(ray, t_min, t_max, March::Course, visit);
    }

    /// [`Grid::walk`] with the march's steps set up as `march` says (a student's march; the
    /// course's inlined into [`Grid::walk`], where its tests fold away).
    ///
    /// One function, long: the 3D-DDA's setup and its stepping loop share a dozen per-axis
    /// values, and the course's cell-by-cell order (and `-stats`' count of cells) depends on
    /// them staying exactly as the handout's algorithm states them, in one place.
    #[inline(always)]
    pub fn walk_marching<'a>(
        &'a self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        march: March,
        mut visit: impl FnMut(Cell<'a>) -> ControlFlow<()>,
    ) {
        // A ray of no direction (a student's square root of a negative number, a zero vector)
        // meets nothing, and would never step out of its first cell.
        if !ray.direction.is_finite() || ray.direction == Vec3A::ZERO {
            return;
        }
        // Where the ray is inside the grid's box, and which face it came in by.
        let mut t_enter = t_min;
        let mut t_leave = t_max;
        let mut entered_axis = 0;
        let mut best_near = f32::NEG_INFINITY;
        for axis in 0..3 {
            let inv = ray.inv_direction[axis];
            let a = (self.bounds.min[axis] - ray.origin[axis]) * inv;
            let b = (self.bounds.max[axis] - ray.origin[axis]) * inv;
            let (near, far) = if a <= b { (a, b) } else { (b, a) };
            // A ray along a face's plane: NaN, where it is as good as inside on that axis.
            if near.is_nan() || far.is_nan() {
                continue;
            }
            if near > best_near {
                best_near = near;
                entered_axis = axis;
            }
            t_enter = t_enter.max(near);
            t_leave = t_leave.min(far);
        }
        if t_enter > t_leave {
            return;
        }
        let start = ray.at(t_enter);
        let mut index = UVec3::ZERO;
        let mut step = [0i64; 3];
        let mut t_next = [f32::INFINITY; 3];
        let mut t_delta = [f32::INFINITY; 3];
        for axis in 0..3 {
            let n = self.cells[axis];
            let offset = (start[axis] - self.bounds.min[axis]) / self.cell_size[axis];
            let i = (offset.floor().max(0.0) as u32).min(n - 1);
            index[axis] = i;
            let d = ray.direction[axis];
            let size = self.cell_size[axis];
            if d > 0.0 {
                step[axis] = 1;
                let boundary = self.bounds.min[axis] + (i + 1) as f32 * size;
                t_next[axis] = (boundary - ray.origin[axis]) * ray.inv_direction[axis];
                t_delta[axis] = size * ray.inv_direction[axis];
            } else if d < 0.0 {
                step[axis] = -1;
                let face = if march == March::UpperFaceFirst {
                    i + 1
                } else {
                    i
                };
                let boundary = self.bounds.min[axis] + face as f32 * size;
                t_next[axis] = (boundary - ray.origin[axis]) * ray.inv_direction[axis];
                t_delta[axis] = if march == March::SignedStep {
                    size * ray.inv_direction[axis]
                } else {
                    -size * ray.inv_direction[axis]
                };
            }
        }
        let mut entered_sign = if ray.direction[entered_axis] > 0.0 {
            -1.0
        } else {
            1.0
        };
        let mut t_cell = t_enter;
        loop {
            // The lecture's choice of the next axis: the smallest next t; its comparisons are
            // strict, so a tie goes to the later axis.
            let axis = if t_next[0] < t_next[1] {
                if t_next[0] < t_next[2] { 0 } else { 2 }
            } else if t_next[1] < t_next[2] {
                1
            } else {
                2
            };
            let t_exit = t_next[axis].min(t_leave);
            let cell = Cell {
                index,
                primitives: self.primitives(index),
                t_enter: t_cell,
                t_exit,
                entered_axis,
                entered_sign,
            };
            if visit(cell).is_break() || t_next[axis] > t_leave {
                return;
            }
            let next = index[axis] as i64 + step[axis];
            if next < 0 || next >= self.cells[axis] as i64 {
                return;
            }
            index[axis] = next as u32;
            t_cell = t_next[axis];
            t_next[axis] += t_delta[axis];
            entered_axis = axis;
            entered_sign = -(step[axis] as f32);
        }
    }
}

/// Calls `f` with the number of every cell that `extent` (widened by `margin`) reaches.
fn grid_fill(
    bounds: &Aabb,
    cells: UVec3,
    cell_size: Vec3A,
    extent: &Extent,
    margin: f32,
    mut f: impl FnMut(usize),
) {
    let reach = extent.reach();
    if reach.is_empty() {
        return;
    }
    let index = |p: Vec3A| {
        let o = (p - bounds.min) / cell_size;
        UVec3::new(
            (o.x.floor().max(0.0) as u32).min(cells.x - 1),
            (o.y.floor().max(0.0) as u32).min(cells.y - 1),
            (o.z.floor().max(0.0) as u32).min(cells.z - 1),
        )
    };
    let (lo, hi) = (index(reach.min - margin), index(reach.max + margin));
    // The student's loop stops before the highest corner's cell: an empty range where the box
    // lies within one cell on an axis.
    let end = match extent {
        Extent::BoxShortOfItsEnd(_) => index(reach.max),
        _ => hi + UVec3::ONE,
    };
    let half_diagonal = 0.5 * cell_size.length();
    for z in lo.z..end.z {
        for y in lo.y..end.y {
            for x in lo.x..end.x {
                let from_centre = |center: Vec3A| {
                    let centre = bounds.min + (UVec3::new(x, y, z).as_vec3a() + 0.5) * cell_size;
                    (centre - center).length()
                };
                let outside = match *extent {
                    Extent::Sphere { center, radius } => {
                        from_centre(center) > radius + half_diagonal + margin
                    }
                    Extent::SphereByCentres { center, radius } => from_centre(center) > radius,
                    Extent::Box(_) | Extent::BoxShortOfItsEnd(_) => false,
                };
                if outside {
                    continue;
                }
                f((x + cells.x * (y + cells.y * z)) as usize);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::accel::test_uniform as lcg;

    #[test]
    fn every_cell_a_primitive_touches_lists_it() {
        let mut seed = 7;
        for case in 0..40 {
            let cells = UVec3::new(1 + case % 7, 1 + case % 5, 1 + case % 3);
            let mut primitives = Vec::new();
            let mut shapes = Vec::new();
            for k in 0..20 {
                let centre = Vec3A::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 8.0 - 4.0;
                let size = Vec3A::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 2.0;
                let extent = if k % 3 == 0 {
                    Extent::Sphere {
                        center: centre,
                        radius: size.x,
                    }
                } else {
                    Extent::Box(Aabb {
                        min: centre - size,
                        max: centre + size,
                    })
                };
                primitives.push((
                    Primitive {
                        item: k,
                        triangle: 0,
                    },
                    extent,
                ));
                shapes.push(extent);
            }
            let bounds = Aabb {
                min: Vec3A::splat(-6.5),
                max: Vec3A::splat(6.5),
            };
            let grid = Grid::build(bounds, cells, &primitives).unwrap();
            for (k, shape) in shapes.iter().enumerate() {
                // Points inside the shape: the cell holding each must list it.
                for _ in 0..200 {
                    let r = Vec3A::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed));
                    let point = match *shape {
                        Extent::Box(b) => b.min + r * (b.max - b.min),
                        Extent::Sphere { center, radius } => {
                            let d = (r * 2.0 - 1.0).normalize_or_zero();
                            center + d * radius * lcg(&mut seed)
                        }
                        _ => unreachable!("only the course's extents are made here"),
                    };
                    let o = (point - grid.bounds.min) / grid.cell_size;
                    let index = UVec3::new(
                        (o.x.floor().max(0.0) as u32).min(cells.x - 1),
                        (o.y.floor().max(0.0) as u32).min(cells.y - 1),
                        (o.z.floor().max(0.0) as u32).min(cells.z - 1),
                    );
                    let c = grid.cell_number(index);
                    let listed =
                        &grid.entries[grid.starts[c] as usize..grid.starts[c + 1] as usize];
                    assert!(
                        listed.iter().any(|p| p.item == k as u32),
                        "case {case}: {shape:?} at {point} not in cell {index}"
                    );
                }
            }
        }
    }

    /// The cells each of the students' listings picks, on a grid of 4 × 4 × 4 unit cells.
    #[test]
    fn students_listings_leave_out_the_cells_they_should() {
        let bounds = Aabb {
            min: Vec3A::ZERO,
            max: Vec3A::splat(4.0),
        };
        let listed = |extent: Extent| {
            let p = Primitive {
                item: 0,
                triangle: 0,
            };
            let grid = Grid::build(bounds, UVec3::splat(4), &[(p, extent)]).unwrap();
            (0..64)
                .filter(|&c| grid.starts[c + 1] > grid.starts[c])
                .collect::<Vec<usize>>()
        };
        // A sphere of radius 1.2 about (2, 2, 2): its centre is a corner of the eight middle
        // cells, whose centres lie 0.87 from it; the cells next to them along an axis have
        // centres 1.66 away, which the sphere passes through without holding.
        let (center, radius) = (Vec3A::splat(2.0), 1.2);
        let middle: Vec<usize> = [21, 22, 25, 26, 37, 38, 41, 42].to_vec();
        assert_eq!(listed(Extent::SphereByCentres { center, radius }), middle);
        assert!(listed(Extent::Sphere { center, radius }).len() > middle.len());
        // A box from 0.5 to 2.5 on x, within cell 1 on y and z: cells 0 and 1 on x, not 2, and
        // nothing at all where the box lies within one cell on an axis.
        let b = Aabb {
            min: Vec3A::new(0.5, 1.2, 1.2),
            max: Vec3A::new(2.5, 1.8, 1.8),
        };
        assert_eq!(listed(Extent::Box(b)).len(), 3);
        assert_eq!(listed(Extent::BoxShortOfItsEnd(b)), Vec::<usize>::new());
        let tall = Aabb {
            min: Vec3A::new(0.5, 0.5, 0.5),
            max: Vec3A::new(2.5, 1.5, 1.5),
        };
        // x 0..2, y 0..1, z 0..1: the cells 0 and 1 on x at y = 0, z = 0.
        assert_eq!(listed(Extent::BoxShortOfItsEnd(tall)), vec![0, 1]);
    }

    /// A grid of 4 × 4 × 4 unit cells from the origin, listing nothing.
    fn empty_grid() -> Grid {
        let bounds = Aabb {
            min: Vec3A::ZERO,
            max: Vec3A::splat(4.0),
        };
        Grid::build(bounds, UVec3::splat(4), &[]).unwrap()
    }

    #[test]
    fn a_ray_of_no_direction_visits_nothing_and_ends() {
        let grid = empty_grid();
        // A refracted direction past the critical angle taken as the square root of a negative
        // number (a student's tracer, which check renders), and a zero vector: before, the walk
        // stepped by nothing, forever.
        for direction in [Vec3A::NAN, Vec3A::ZERO] {
            let ray = Ray::new(Vec3A::splat(1.5), direction);
            let mut visits = 0;
            grid.walk(&ray, 0.0, f32::INFINITY, |_| {
                visits += 1;
                if visits > 100 {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            });
            assert_eq!(visits, 0, "{direction}");
        }
    }

    #[test]
    fn the_walk_visits_cells_in_order_along_the_ray() {
        let grid = empty_grid();
        // Along x through the middle of row (·, 1, 2): four cells, entered through -x faces.
        let ray = Ray::new(Vec3A::new(-1.0, 1.5, 2.5), Vec3A::X);
        let mut visited = Vec::new();
        grid.walk(&ray, 0.0, f32::INFINITY, |cell| {
            visited.push((
                cell.index,
                cell.t_enter,
                cell.t_exit,
                cell.entered_axis,
                cell.entered_sign,
            ));
            ControlFlow::Continue(())
        });
        assert_eq!(
            visited,
            [
                (UVec3::new(0, 1, 2), 1.0, 2.0, 0, -1.0),
                (UVec3::new(1, 1, 2), 2.0, 3.0, 0, -1.0),
                (UVec3::new(2, 1, 2), 3.0, 4.0, 0, -1.0),
                (UVec3::new(3, 1, 2), 4.0, 5.0, 0, -1.0),
            ]
        );
        // A diagonal from inside: from (0.5, 0.5, 0.5) along +x+y both boundaries come at
        // t = 0.5; the lecture's strict comparison steps y first, then x.
        let ray = Ray::new(Vec3A::splat(0.5), Vec3A::new(1.0, 1.0, 0.0));
        let mut cells = Vec::new();
        grid.walk(&ray, 0.0, f32::INFINITY, |cell| {
            cells.push(cell.index);
            ControlFlow::Continue(())
        });
        assert_eq!(
            cells[..3],
            [
                UVec3::new(0, 0, 0),
                UVec3::new(0, 1, 0),
                UVec3::new(1, 1, 0)
            ]
        );
        // A ray that misses the grid visits nothing.
        let miss = Ray::new(Vec3A::new(-1.0, 9.0, 0.0), Vec3A::X);
        let mut any = false;
        grid.walk(&miss, 0.0, f32::INFINITY, |_| {
            any = true;
            ControlFlow::Continue(())
        });
        assert!(!any);
    }

    #[test]
    fn students_marches_down_an_axis_by_hand() {
        let grid = empty_grid();
        // From x = 5 down the x axis through the row of cells at y = 1, z = 2: the course
        // enters cell 3 at t = 1 and leaves each cell a unit of t later.
        let ray = Ray::new(Vec3A::new(5.0, 1.5, 2.5), -Vec3A::X);
        let cells = |march: March| {
            let mut cells = Vec::new();
            grid.walk_marching(&ray, 0.0, f32::INFINITY, march, |cell| {
                cells.push((cell.index.x, cell.t_enter, cell.t_exit));
                ControlFlow::Continue(())
            });
            cells
        };
        let course = [(3, 1.0, 2.0), (2, 2.0, 3.0), (1, 3.0, 4.0), (0, 4.0, 5.0)];
        assert_eq!(cells(March::Course), course);
        // The first crossing at the upper face, x = 4, already behind: the march is a cell
        // ahead of the ray, and leaves the grid a cell early.
        assert_eq!(
            cells(March::UpperFaceFirst),
            [(3, 1.0, 1.0), (2, 1.0, 2.0), (1, 2.0, 3.0), (0, 3.0, 4.0)]
        );
        // Each step's t negative: every crossing after the first is taken at once.
        assert_eq!(
            cells(March::SignedStep),
            [(3, 1.0, 2.0), (2, 2.0, 1.0), (1, 1.0, 0.0), (0, 0.0, -1.0)]
        );
    }
}
