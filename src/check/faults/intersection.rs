//! Faults of the search for the nearest hit: the range of t it accepts.

use super::{Candidate, Fault, LineScene, Planted};
use crate::accel::{Carry, Hit, Listing, March, Struck};
use crate::camera::Camera;
use crate::geometry::{Plane, Ray, Transform, intersect_plane, sphere_roots};
use crate::parse::description::{Projection, Shape};
use crate::scene::Scene;
use glam::Vec3A;

/// How a student's tracer takes the nearest hit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum HitFault {
    /// Camera rays accept hits from this t on (the course: the orthographic camera sees behind
    /// its centre, the perspective camera only in front of its eye).
    CameraTMin(f32),
    /// Hits farther than this distance are lost (a finite "infinity").
    Limit(f32),
    /// Hits nearer than this distance are skipped, for every picture (the depth picture's
    /// near end used as the rays' t_min).
    Nearer(f32),
    /// Normals carried into the world by the object's matrix, not its inverse transpose.
    NormalByMatrix,
    /// Normals carried by the inverse of the object's matrix, not transposed.
    NormalByInverse,
    /// Normals carried by the transpose of the object's matrix, not of its inverse.
    NormalByTranspose,
    /// Normals carried by the inverse transpose but not made unit length again.
    NormalNotUnit,
    /// Each object's t measured along its own space's ray made unit length (1), or the world's
    /// t times another power of that space's stretch along the ray (the fit's number).
    ObjectSpaceT(f32),
    /// Triangles refused where the determinant of the handout's system is below this in
    /// magnitude.
    DeterminantEpsilon(f32),
    /// Triangles refused where a barycentric coordinate is within this of an edge.
    EdgeEpsilon(f32),
    /// The grid's search stopped at the first cell with any hit in it.
    FirstCellHit,
    /// The grid's search testing each primitive once, a hit beyond its cell dropped for good.
    Mailboxed,
    /// With a grid, objects under a Transform listed in the cells of another box than the
    /// course's.
    ListedBy(Listing),
    /// With a grid, a ray that begins inside its box walked nowhere: it meets the planes alone.
    WalkedFromOutside,
    /// With a grid, the planes never tested (they have no box, so they are in no cell).
    PlanesUntested,
    /// With a grid, the planes listed in the cells they cross: met only inside the grid's box.
    PlanesInGridBox,
    /// Each plane met where n·P + d = 0, not n·P = d: as far on the other side of the origin.
    PlaneOffsetNegated,
    /// Every triangle's normal turned the other way: (c − a) × (b − a).
    TriangleNormalTurned,
    /// A triangle's normal the cross product of its edges, never made unit: twice its area
    /// long (a Transform, normalising what it carries, hides it).
    TriangleNormalUnit,
    /// A sphere's normal p − c, never divided by the radius (a Transform hides it too).
    SphereNormalUnit,
    /// Normals of the length check's shading fit found: see [`normal_length`].
    NormalLength([f32; 3]),
    /// A sphere met only at one root of its quadratic: the nearer (`far` false), so a ray
    /// that starts inside misses it, or the farther, so its far side shows.
    SphereRoot {
        /// The farther root, not the nearer.
        far: bool,
    },
    /// Each object under a Transform meets the ray carried into its space another way than
    /// the course's.
    RayCarried(Carry),
    /// With a grid, the march's steps set up another way along an axis the ray runs down.
    Marched(March),
}

/// The length of a normal of unit direction `normal` on an object placed by `transform`, as a
/// student's tracer leaves it: 1/|n|² = a + b |Aᵀn|² + c (t·n)², A and t the Transform's linear
/// part and translation; unit in world space, where no Transform carries it (a length that is
/// the same everywhere would stand in for any factor of the light's). The course's is
/// (1, 0, 0); a normal
/// carried by the inverse transpose and not made unit again is (0, 1, 0); one carried as the
/// 4-vector (n, 0) by the whole inverse transpose and normalised with its fourth component,
/// (1, 0, 1).
pub fn normal_length(numbers: [f32; 3], normal: Vec3A, transform: Option<&Transform>) -> f32 {
    length_from(numbers, normal_stretch(normal, transform))
}

/// For [`normal_length`]: |Aᵀn|² and t·n, where a Transform carries the normal.
pub fn normal_stretch(normal: Vec3A, transform: Option<&Transform>) -> Option<(f32, f32)> {
    transform.map(|t| {
        (
            (t.object_to_world.matrix3.transpose() * normal).length_squared(),
            t.object_to_world.translation.dot(normal),
        )
    })
}

/// [`normal_length`] from [`normal_stretch`]'s numbers (0 where the numbers give no length).
pub fn length_from([a, b, c]: [f32; 3], stretch: Option<(f32, f32)>) -> f32 {
    let Some((stretched, along)) = stretch else {
        return 1.0;
    };
    let inverse_square = a + b * stretched + c * along * along;
    if inverse_square > 0.0 {
        inverse_square.sqrt().recip()
    } else {
        0.0
    }
}

/// The handout's triangle test by Cramer's rule, for `ray` against corners a, b and c: the
/// determinant of the system [a − b, a − c, d] and the barycentric β and γ of the point it
/// meets.
fn cramer(ray: &Ray, [a, b, c]: &[glam::Vec3; 3]) -> (f32, f32, f32) {
    let (a, b, c) = (
        glam::Vec3A::from(*a),
        glam::Vec3A::from(*b),
        glam::Vec3A::from(*c),
    );
    let (ab, ac, d) = (a - b, a - c, ray.direction);
    let ae = a - ray.origin;
    let det = ab.dot(ac.cross(d));
    let beta = ae.dot(ac.cross(d)) / det;
    let gamma = ab.dot(ae.cross(d)) / det;
    (det, beta, gamma)
}

impl HitFault {
    pub(super) fn camera_t_min(&self, _camera: &Camera) -> Option<f32> {
        match *self {
            HitFault::CameraTMin(t) => Some(t),
            _ => None,
        }
    }

    /// Whether the student's shadow rays go through the search this fault plants (a grid of
    /// their own stops their shadow rays as it finds their camera rays' hits).
    pub(super) fn searches_shadows(&self) -> bool {
        matches!(
            self,
            HitFault::ListedBy(_)
                | HitFault::WalkedFromOutside
                | HitFault::SphereRoot { .. }
                | HitFault::RayCarried(_)
                | HitFault::Marched(_)
        )
    }

    pub(super) fn found(
        &self,
        scene: &Scene,
        ray: &Ray,
        t_min: f32,
        hit: Option<Hit>,
    ) -> Option<Hit> {
        // Distances along the ray as a student's unit-direction ray would measure them.
        let length = ray.direction.length();
        match *self {
            HitFault::CameraTMin(_) => hit,
            HitFault::ObjectSpaceT(power) => scene.world.intersect_stretched_t(ray, t_min, power),
            HitFault::FirstCellHit => scene.world.intersect_first_cell(ray, t_min),
            HitFault::SphereRoot { far } => {
                scene
                    .world
                    .intersect_spheres_by(ray, t_min, |local, sphere, t_min, t_max| {
                        let (near, farther) = sphere_roots(local, sphere)?;
                        let t = if far { farther } else { near };
                        (t >= t_min && t <= t_max).then_some(t)
                    })
            }
            HitFault::RayCarried(carry) => scene.world.intersect_carried(ray, t_min, carry),
            HitFault::Marched(march) => scene.world.intersect_marched(ray, t_min, march),
            HitFault::Mailboxed => scene.world.intersect_mailboxed(ray, t_min),
            HitFault::ListedBy(listed) => scene.world.intersect_listed_by(listed, ray, t_min),
            HitFault::WalkedFromOutside => scene.world.intersect_walked_from_outside(ray, t_min),
            HitFault::PlanesUntested => {
                scene
                    .world
                    .intersect_planes_by(ray, t_min, |_, _, _, _| None)
            }
            HitFault::PlanesInGridBox => {
                let within = scene.world.grid().map(|grid| grid.bounds());
                scene
                    .world
                    .intersect_planes_by(ray, t_min, |ray, plane, t_min, t_max| {
                        let t = intersect_plane(ray, plane, t_min, t_max)?;
                        within
                            .is_some_and(|within| within.contains(ray.at(t)))
                            .then_some(t)
                    })
            }
            HitFault::TriangleNormalTurned
            | HitFault::TriangleNormalUnit
            | HitFault::SphereNormalUnit => {
                let (hit, struck) = scene.world.intersect_noting(ray, t_min)?;
                // The factor the student's normal is of the course's (a Transform normalises
                // what it carries).
                let factor = match (*self, struck) {
                    (HitFault::TriangleNormalTurned, Struck::Triangle { .. }) => -1.0,
                    (
                        HitFault::TriangleNormalUnit,
                        Struck::Triangle {
                            corners: [a, b, c],
                            transformed: false,
                        },
                    ) => (b - a).cross(c - a).length(),
                    (
                        HitFault::SphereNormalUnit,
                        Struck::Sphere {
                            radius,
                            transformed: false,
                        },
                    ) => radius,
                    _ => 1.0,
                };
                Some(Hit {
                    normal: hit.normal * factor,
                    ..hit
                })
            }
            HitFault::PlaneOffsetNegated => {
                scene
                    .world
                    .intersect_planes_by(ray, t_min, |ray, plane, t_min, t_max| {
                        let moved = Plane {
                            offset: -plane.offset,
                            ..*plane
                        };
                        intersect_plane(ray, &moved, t_min, t_max)
                    })
            }
            HitFault::DeterminantEpsilon(epsilon) => {
                scene
                    .world
                    .intersect_accepting(ray, t_min, |local, corners| {
                        cramer(local, corners).0.abs() >= epsilon
                    })
            }
            HitFault::EdgeEpsilon(epsilon) => {
                scene
                    .world
                    .intersect_accepting(ray, t_min, |local, corners| {
                        let (_, beta, gamma) = cramer(local, corners);
                        beta >= epsilon && gamma >= epsilon && beta + gamma <= 1.0 - epsilon
                    })
            }
            HitFault::Limit(limit) => hit.filter(|h| h.t * length <= limit),
            HitFault::Nearer(near) => match hit {
                Some(h) if h.t * length < near => scene.world.intersect(ray, near / length),
                other => other,
            },
            HitFault::NormalLength(numbers) => {
                let hit = hit?;
                let transform = scene.world.normal_origin(ray, t_min).and_then(|(_, t)| t);
                Some(Hit {
                    normal: hit.normal * normal_length(numbers, hit.normal, transform),
                    ..hit
                })
            }
            HitFault::NormalByMatrix
            | HitFault::NormalByInverse
            | HitFault::NormalByTranspose
            | HitFault::NormalNotUnit => {
                let hit = hit?;
                let Some((object_normal, Some(transform))) = scene.world.normal_origin(ray, hit.t)
                else {
                    return Some(hit);
                };
                let object_normal = object_normal.normalize_or_zero();
                let matrix = transform.object_to_world.matrix3;
                let normal = match self {
                    HitFault::NormalByMatrix => (matrix * object_normal).normalize_or_zero(),
                    HitFault::NormalByInverse => {
                        (transform.world_to_object.matrix3 * object_normal).normalize_or_zero()
                    }
                    HitFault::NormalByTranspose => {
                        (matrix.transpose() * object_normal).normalize_or_zero()
                    }
                    _ => transform.normal_to_world * object_normal,
                };
                Some(Hit {
                    normal: if normal == glam::Vec3A::ZERO {
                        hit.normal
                    } else {
                        normal
                    },
                    ..hit
                })
            }
        }
    }
}

/// Whether the line's scene places something under a Transform, and the line shows normals
/// (in the normals picture, or in shading with lights).
fn transformed_normals_show(line: &LineScene) -> bool {
    let placed = line
        .description
        .objects
        .iter()
        .any(|o| o.transform.is_some());
    let shows =
        line.options.normals.is_some() || (line.has_image() && !line.scene.lights.is_empty());
    placed && shows
}

pub(super) const NORMAL_TRANSFORM: Fault = Fault {
    name: "normal_transform",
    assignment: 2,
    sentence: "I carry normals into the world with another matrix than the transpose of the \
               object's inverse (form 0: the matrix itself; 1: its inverse; 2: its transpose).",
    look_for: "The normal of a transformed object: n_world = (M^-1)^T n_object, then normalised; \
               M itself tilts normals of scaled or sheared objects.",
    candidates: |line: &LineScene| {
        if transformed_normals_show(line) {
            Candidate::forms(
                [
                    HitFault::NormalByMatrix,
                    HitFault::NormalByInverse,
                    HitFault::NormalByTranspose,
                ]
                .map(Planted::Hit),
            )
        } else {
            Vec::new()
        }
    },
};

pub(super) const NORMAL_LENGTH: Fault = Fault {
    name: "normal_length",
    assignment: 2,
    sentence: "My normals are not unit length after a Transform.",
    look_for: "After carrying a normal into the world by the inverse transpose, normalise it \
               again: a scale changes its length.",
    candidates: |line: &LineScene| {
        if transformed_normals_show(line) {
            vec![Candidate::plain(Planted::Hit(HitFault::NormalNotUnit))]
        } else {
            Vec::new()
        }
    },
};

fn t_min_ignored(line: &LineScene) -> Vec<Candidate> {
    // The other of the two choices: hits behind a perspective camera's eye accepted, or an
    // orthographic camera that sees nothing behind its centre.
    let t_min = match line.description.camera.projection {
        Projection::Perspective { .. } => f32::NEG_INFINITY,
        Projection::Orthographic { .. } => 0.0,
    };
    vec![Candidate::with(
        Planted::Hit(HitFault::CameraTMin(t_min)),
        "t_min",
        f64::from(t_min),
    )]
}

pub(super) const T_MIN_IGNORED: Fault = Fault {
    name: "t_min_ignored",
    assignment: 1,
    sentence: "My camera rays take hits on the wrong side of their start: behind a perspective \
               camera's eye, or none behind an orthographic camera's centre.",
    look_for: "The tmin a camera ray passes to intersect: 0 for the perspective camera (only \
               what is in front of the eye), -infinity for the orthographic camera.",
    candidates: t_min_ignored,
};

fn t_limit(line: &LineScene) -> Vec<Candidate> {
    if !line.has_image() && !line.has_depth_or_normals() {
        return Vec::new();
    }
    [1.0f32, 10.0, 100.0, 1000.0]
        .into_iter()
        .map(|limit| {
            Candidate::with(
                Planted::Hit(HitFault::Limit(limit)),
                "limit",
                f64::from(limit),
            )
        })
        .collect()
}

pub(super) const T_LIMIT: Fault = Fault {
    name: "t_limit",
    assignment: 1,
    sentence: "My nearest-hit search starts from a finite \"infinity\", so far surfaces are lost.",
    look_for: "The initial t of the hit record: start from a value larger than any hit (such as \
               FLT_MAX or infinity), not from 1 or 1000.",
    candidates: t_limit,
};

fn depth_tmin(line: &LineScene) -> Vec<Candidate> {
    match line.options.depth {
        Some((near, _, _)) if near > 0.0 => vec![Candidate::with(
            Planted::Hit(HitFault::Nearer(near)),
            "t_min",
            f64::from(near),
        )],
        _ => Vec::new(),
    }
}

pub(super) const DEPTH_TMIN: Fault = Fault {
    name: "depth_tmin",
    assignment: 2,
    sentence: "My rays start at the depth picture's near end, so what is nearer is cut away.",
    look_for: "The depth range only maps t to grey: the rays still start at the camera's own \
               tmin, and t nearer than -depth's TMIN is white, not skipped.",
    candidates: depth_tmin,
};

/// Whether the line's scene places something under a Transform that changes lengths.
pub(crate) fn lengths_change(line: &LineScene) -> bool {
    line.description.objects.iter().any(|o| {
        o.transform.is_some_and(|t| {
            let m = glam::DMat3::from_mat4(line.description.transforms[t as usize]);
            !(m.transpose() * m).abs_diff_eq(glam::DMat3::IDENTITY, 1e-6)
        })
    })
}

pub(super) const OBJECT_SPACE_T: Fault = Fault {
    name: "object_space_t",
    assignment: 2,
    sentence: "I normalise the ray after carrying it into a transformed object's space, so that \
               object's t is not the world's: the nearer object can lose, and the hit point and \
               depth are off.",
    look_for: "Transform::intersect: carry the ray into object space without normalising its \
               direction (then t means the same in both spaces), or convert the object-space t \
               back by the direction's length.",
    candidates: |line: &LineScene| {
        if lengths_change(line) {
            vec![Candidate::plain(Planted::Hit(HitFault::ObjectSpaceT(1.0)))]
        } else {
            Vec::new()
        }
    },
};

/// Whether the line's scene has triangles (loose, or of a mesh).
pub(crate) fn has_triangles(line: &LineScene) -> bool {
    line.scene.world.stats().triangles > 0
}

pub(super) const TRIANGLE_EPSILON: Fault = Fault {
    name: "triangle_epsilon",
    assignment: 2,
    sentence: "My triangle test refuses hits by an absolute epsilon: on the determinant (small \
               or thin triangles vanish) or on the barycentric coordinates (cracks along the \
               edges).",
    look_for: "The triangle test: a hit is refused only where the determinant is exactly 0 (or \
               by an epsilon relative to the triangle's size), and β ≥ 0, γ ≥ 0, β + γ ≤ 1 \
               without an epsilon.",
    candidates: |line: &LineScene| {
        if !has_triangles(line) {
            return Vec::new();
        }
        let determinants = [1e-2f32, 1e-3, 1e-4, 1e-5, 1e-6].map(|e| {
            Candidate::with(
                Planted::Hit(HitFault::DeterminantEpsilon(e)),
                "determinant_epsilon",
                f64::from(e),
            )
        });
        let edges = [1e-2f32, 1e-3].map(|e| {
            Candidate::with(
                Planted::Hit(HitFault::EdgeEpsilon(e)),
                "edge_epsilon",
                f64::from(e),
            )
        });
        determinants.into_iter().chain(edges).collect()
    },
};

/// Whether the line's traced pictures are searched through the course's grid (`-grid`, and not
/// `-visualize_grid`, whose picture is the cells): where a grid fault can show.
fn grid_searched(line: &LineScene) -> bool {
    line.scene.world.grid().is_some()
        && !line.options.trace.visualize_grid
        && line.has_traced_picture()
}

pub(super) const GRID_FIRST_HIT: Fault = Fault {
    name: "grid_first_hit",
    assignment: 5,
    sentence: "My grid walk trusts a hit beyond the cell that found it: it returns it at once, so \
               an object listed in several cells can hide a nearer one (form 0), or it marks the \
               object as tested and drops the hit, so the object vanishes where the ray meets it \
               in a later cell (form 1).",
    look_for: "The grid's ray march: a hit found while visiting a cell counts only if its t is \
               within that cell (t ≤ the cell's exit); otherwise keep marching, test the object \
               again (or keep its hit) in the cell where the hit lies, and compare with the later \
               cells' hits.",
    candidates: |line: &LineScene| {
        if grid_searched(line) {
            Candidate::forms([HitFault::FirstCellHit, HitFault::Mailboxed].map(Planted::Hit))
        } else {
            Vec::new()
        }
    },
};

pub(super) const GRID_TRANSFORMED_BOX: Fault = Fault {
    name: "grid_transformed_box",
    assignment: 5,
    sentence: "My grid lists an object under a Transform by the wrong box: its own box with \
               the Transform left out (form 0), or the box between its lowest and highest \
               corners carried into the world (form 1). Where the object reaches past that box, \
               the cells there do not list it, and it is cut away, in its shadows too.",
    look_for: "Transform's insertIntoGrid: carry all eight corners of the object's box by the \
               matrix, and list the object in every cell of the box around them.",
    candidates: |line: &LineScene| {
        let placed = line
            .description
            .objects
            .iter()
            .any(|o| o.transform.is_some());
        if grid_searched(line) && placed {
            Candidate::forms(
                [Listing::Untransformed, Listing::TwoCorners]
                    .map(|listed| Planted::Hit(HitFault::ListedBy(listed))),
            )
        } else {
            Vec::new()
        }
    },
};

pub(super) const GRID_CELLS_MISSED: Fault = Fault {
    name: "grid_cells_missed",
    assignment: 5,
    sentence: "My grid lists an object in too few cells: a sphere only in the cells whose \
               centres lie inside it (form 0), or every object only in the cells before the one \
               its box ends in, a loop's bound written with < (form 1). A ray crossing a cell \
               left out passes through the object there, and its shadow has the same holes.",
    look_for: "insertIntoGrid: list an object in every cell its box overlaps, from the cell of \
               its lowest corner to the cell of its highest one, both included (<=); for a \
               sphere tested by the cells' centres, widen the radius by half a cell's diagonal \
               so that no cell the sphere passes through is missed.",
    candidates: |line: &LineScene| {
        if !grid_searched(line) {
            return Vec::new();
        }
        let world = &line.scene.world;
        let spheres = world
            .grid_primitives()
            .any(|(p, _, placed)| placed.is_none() && world.primitive_sphere(&p).is_some());
        let listings = [Listing::SphereByCentres, Listing::ShortOfTheEnd];
        listings
            .into_iter()
            .enumerate()
            .filter(|&(_, listed)| spheres || listed != Listing::SphereByCentres)
            .map(|(form, listed)| {
                Candidate::with(
                    Planted::Hit(HitFault::ListedBy(listed)),
                    "form",
                    form as f64,
                )
            })
            .collect()
    },
};

pub(super) const GRID_RAYS_FROM_INSIDE: Fault = Fault {
    name: "grid_rays_from_inside",
    assignment: 5,
    sentence: "My grid walk starts only where a ray enters the grid's box from outside: a ray \
               that begins inside it (every shadow, mirror and glass ray leaving a surface in \
               the grid) meets nothing the grid holds, so the objects cast no shadows and show \
               in no mirror or glass.",
    look_for: "Where the grid's march begins: a ray whose origin is inside the grid's box \
               starts in the cell that holds its origin (t = tmin), not only at the box's entry \
               (whose t is then negative).",
    candidates: |line: &LineScene| {
        let inner_rays = line.options.trace.shadows || line.options.trace.bounces > 0;
        if grid_searched(line) && inner_rays {
            vec![Candidate::plain(Planted::Hit(HitFault::WalkedFromOutside))]
        } else {
            Vec::new()
        }
    },
};

pub(super) const PLANE_OFFSET_SIGN: Fault = Fault {
    name: "plane_offset_sign",
    assignment: 2,
    sentence: "My plane test takes the offset with the wrong sign, n·P + d = 0 where the course \
               means n·P = d: the plane stands as far on the other side of the origin.",
    look_for: "Plane { normal n offset d } is the points P with n·P = d: the ray O + tD meets it \
               at t = (d − n·O) / (n·D).",
    candidates: |line: &LineScene| {
        let pictures = line.has_traced_picture();
        let moved = line
            .scene
            .world
            .planes()
            .iter()
            .any(|(plane, _)| plane.offset != 0.0);
        if pictures && moved {
            vec![Candidate::plain(Planted::Hit(HitFault::PlaneOffsetNegated))]
        } else {
            Vec::new()
        }
    },
};

pub(super) const TRIANGLE_WINDING: Fault = Fault {
    name: "triangle_winding",
    assignment: 2,
    sentence: "My triangle's normal is the cross product in the other order, (c − a) × (b − a): \
               every triangle faces the other way.",
    look_for: "Triangle a, b, c: its normal is (b − a) × (c − a), made unit length (the corners \
               counter-clockwise seen from its front).",
    candidates: |line: &LineScene| {
        if has_triangles(line) && line.has_image() {
            vec![Candidate::plain(Planted::Hit(
                HitFault::TriangleNormalTurned,
            ))]
        } else {
            Vec::new()
        }
    },
};

pub(super) const TRIANGLE_NORMAL_LENGTH: Fault = Fault {
    name: "triangle_normal_length",
    assignment: 2,
    sentence: "My triangle's normal is the cross product of two edges, never made unit length: \
               twice the triangle's area long, so small triangles shade dark and large ones \
               bright.",
    look_for: "Triangle's intersect: normalise (b − a) × (c − a) before it is used (or stored).",
    candidates: |line: &LineScene| {
        if has_triangles(line) && line.has_traced_picture() {
            vec![Candidate::plain(Planted::Hit(HitFault::TriangleNormalUnit))]
        } else {
            Vec::new()
        }
    },
};

pub(super) const SPHERE_NORMAL_LENGTH: Fault = Fault {
    name: "sphere_normal_length",
    assignment: 2,
    sentence: "My sphere's normal is the point minus the centre, never divided by the radius: \
               as long as the radius, so a large sphere shades bright and a small one dark.",
    look_for: "Sphere's intersect: the normal is (p − center) / radius (or normalised).",
    candidates: |line: &LineScene| {
        let sphere_not_unit = line.description.objects.iter().any(|o| {
            o.transform.is_none()
                && matches!(o.shape, Shape::Sphere { radius, .. } if radius != 1.0)
        });
        if sphere_not_unit && line.has_traced_picture() {
            vec![Candidate::plain(Planted::Hit(HitFault::SphereNormalUnit))]
        } else {
            Vec::new()
        }
    },
};

pub(super) const SPHERE_ROOT: Fault = Fault {
    name: "sphere_root",
    assignment: 1,
    sentence: "My sphere test takes one root of the quadratic whatever t_min says (form 0: the \
               nearer, (-b - √d) / 2a, so a ray that starts inside a sphere, as a glass ray \
               does, misses it; form 1: the farther, (-b + √d) / 2a, so a sphere shows its far \
               side from within).",
    look_for: "Sphere's intersect: of the two roots, the nearer one if it is at least t_min, \
               else the farther one if that is (a ray that starts inside the sphere meets it \
               on its way out).",
    candidates: |line: &LineScene| {
        let description = &line.description;
        let eye = description.camera.center;
        // Whether a sphere may hold the camera's eye (one under a Transform is not worked
        // out); an orthographic camera's rays take hits behind them, so both roots anyway.
        let perspective = matches!(
            description.camera.projection,
            crate::parse::description::Projection::Perspective { .. }
        );
        let mut holds_camera = false;
        let mut spheres = false;
        for object in &description.objects {
            if let Shape::Sphere { center, radius } = object.shape {
                spheres = true;
                holds_camera |=
                    perspective && (object.transform.is_some() || center.distance(eye) < radius);
            }
        }
        if !spheres || !line.has_traced_picture() {
            return Vec::new();
        }
        // The nearer root alone differs only for rays that start inside a sphere: glass rays,
        // or the camera's from within one.
        let from_inside = holds_camera || (super::bounces(line) && super::has_material(line, true));
        Candidate::forms_shown(
            [false, true].map(|far| Planted::Hit(HitFault::SphereRoot { far })),
            [from_inside, true],
        )
    },
};

pub(super) const RAY_TRANSFORM: Fault = Fault {
    name: "ray_transform",
    assignment: 2,
    sentence: "My Transform carries the ray into the object's space another way than by the \
               inverse of its matrix (form 0: the direction as a point, (d, 1), so the \
               translation bends it; 1: the origin as a direction, (o, 0), so the translation \
               is lost; 2: by the matrix itself, not its inverse).",
    look_for: "Transform's intersect: with M⁻¹ the inverse of the object's matrix, the origin \
               is M⁻¹ (o, 1) and the direction M⁻¹ (d, 0), left unnormalised so that t \
               needs no change on the way back.",
    candidates: |line: &LineScene| {
        let description = &line.description;
        let mut placed = false;
        let mut moved = false;
        for object in &description.objects {
            if let Some(matrix) = object
                .transform
                .and_then(|i| description.transforms.get(i as usize))
            {
                placed = true;
                moved |= matrix.w_axis.truncate() != glam::DVec3::ZERO;
            }
        }
        if !placed || !line.has_traced_picture() {
            return Vec::new();
        }
        // Without a translation, a point and a direction are carried alike.
        Candidate::forms_shown(
            [
                Carry::DirectionAsPoint,
                Carry::OriginAsDirection,
                Carry::ByMatrix,
            ]
            .map(|carry| Planted::Hit(HitFault::RayCarried(carry))),
            [moved, moved, true],
        )
    },
};

pub(super) const GRID_MARCH: Fault = Fault {
    name: "grid_march",
    assignment: 5,
    sentence: "My grid march steps wrongly along an axis the ray runs down: its first crossing \
               taken at the cell's upper face, as for an axis it runs up (form 0), or each \
               step's t left as size / d, negative (form 1): cells are skipped, and the objects \
               in them missed.",
    look_for: "initializeRayMarch: along an axis with d < 0, the first crossing is at the \
               current cell's lower face, min + i × size, the index steps by −1, and each step \
               adds |size / d| to that axis's next t.",
    candidates: |line: &LineScene| {
        if grid_searched(line) && line.has_traced_picture() {
            Candidate::forms(
                [March::UpperFaceFirst, March::SignedStep]
                    .map(|march| Planted::Hit(HitFault::Marched(march))),
            )
        } else {
            Vec::new()
        }
    },
};

pub(super) const GRID_PLANES: Fault = Fault {
    name: "grid_planes",
    assignment: 5,
    sentence: "With the grid on, my planes go missing: they have no box, so they are in no cell \
               and my grid walk never tests them (form 0); or I list them in the cells they \
               cross, so they show only inside the grid's box (form 1).",
    look_for: "Planes have no bounding box: they stay out of the grid and out of the scene's box, \
               and every ray tests them besides the grid's march, as it does without a grid \
               (the nearer of the plane's hit and the march's wins).",
    candidates: |line: &LineScene| {
        if grid_searched(line) && line.scene.world.stats().planes > 0 {
            Candidate::forms(
                [HitFault::PlanesUntested, HitFault::PlanesInGridBox].map(Planted::Hit),
            )
        } else {
            Vec::new()
        }
    },
};

#[cfg(test)]
mod tests {
    use std::path::Path;

    use glam::{UVec3, Vec3A};

    use super::*;
    use crate::parse::parse_scene;

    fn scene(objects: &str) -> Scene {
        let text = format!(
            "OrthographicCamera {{ center 0 0 10 direction 0 0 -1 up 0 1 0 size 2 }}
             Background {{ color 0 0 0 ambientLight 1 1 1 }}
             Materials {{ numMaterials 2 Material {{ diffuseColor 1 0 0 }}
                 Material {{ diffuseColor 0 1 0 }} }}
             {objects}"
        );
        let description = parse_scene(Path::new("t.txt"), &text).unwrap();
        Scene::from_description(&description).unwrap()
    }

    fn found(fault: HitFault, scene: &Scene, ray: &Ray) -> Option<Hit> {
        let hit = scene.world.intersect(ray, 0.0);
        fault.found(scene, ray, 0.0, hit)
    }

    #[test]
    fn a_ray_carried_another_way_by_hand() {
        // A unit sphere moved to x = 2: the course meets it from (2, 0, 10) at t = 9.
        let scene = scene(
            "Group { numObjects 1 MaterialIndex 0
                 Transform { Translate 2 0 0 Sphere { center 0 0 0 radius 1 } } }",
        );
        let down_from = |x: f32| Ray::new(Vec3A::new(x, 0.0, 10.0), -Vec3A::Z);
        let t = |carry, x| found(HitFault::RayCarried(carry), &scene, &down_from(x)).map(|h| h.t);
        assert_eq!(scene.world.intersect(&down_from(2.0), 0.0).unwrap().t, 9.0);
        // The direction as a point, (0, 0, −1, 1): (−2, 0, −1), past the sphere.
        assert_eq!(t(Carry::DirectionAsPoint, 2.0), None);
        // The origin as a direction: the sphere stays at the origin.
        assert_eq!(t(Carry::OriginAsDirection, 2.0), None);
        assert_eq!(t(Carry::OriginAsDirection, 0.0), Some(9.0));
        // By the matrix: moved the other way, to x = −2.
        assert_eq!(t(Carry::ByMatrix, 2.0), None);
        assert_eq!(t(Carry::ByMatrix, -2.0), Some(9.0));
        // The normal where the student's ray meets the sphere: its top seen from above.
        let hit = found(
            HitFault::RayCarried(Carry::ByMatrix),
            &scene,
            &down_from(-2.0),
        )
        .unwrap();
        assert_eq!(hit.normal, Vec3A::Z);
    }

    #[test]
    fn a_sphere_met_at_one_root_by_hand() {
        let scene = scene(
            "Group { numObjects 2
                 MaterialIndex 0 Sphere { center 0 0 0 radius 1 }
                 MaterialIndex 1 Plane { normal 0 1 0 offset -3 } }",
        );
        let (near, far) = (
            HitFault::SphereRoot { far: false },
            HitFault::SphereRoot { far: true },
        );
        let down = Ray::new(Vec3A::new(0.0, 5.0, 0.0), -Vec3A::Y);
        // From outside: the top at t = 4, the bottom (its normal facing down) at t = 6.
        assert_eq!(found(near, &scene, &down).unwrap().t, 4.0);
        let back = found(far, &scene, &down).unwrap();
        assert_eq!((back.t, back.normal), (6.0, -Vec3A::Y));
        // From the centre the nearer root is behind the ray: the floor at y = -3 instead.
        let inside = Ray::new(Vec3A::ZERO, -Vec3A::Y);
        assert_eq!(scene.world.intersect(&inside, 0.0).unwrap().t, 1.0);
        let missed = found(near, &scene, &inside).unwrap();
        assert_eq!((missed.t, missed.material), (3.0, 1));
        assert_eq!(found(far, &scene, &inside).unwrap().t, 1.0);
    }

    #[test]
    fn planes_untested_met_only_inside_the_grids_box_or_on_the_other_side() {
        let mut scene = scene(
            "Group { numObjects 2
                 MaterialIndex 0 Sphere { center 0 0 0 radius 1 }
                 MaterialIndex 1 Plane { normal 0 1 0 offset -1 } }",
        );
        scene.world.use_grid(UVec3::splat(2)).unwrap();
        let down = |x: f32, z: f32| Ray::new(Vec3A::new(x, 5.0, z), -Vec3A::Y);
        // Beside the sphere, over the grid's box and beyond it: the course meets the floor.
        for ray in [down(0.5, 0.9), down(3.0, 0.0)] {
            let hit = scene.world.intersect(&ray, 0.0).unwrap();
            assert_eq!((hit.t, hit.material), (6.0, 1));
            assert!(found(HitFault::PlanesUntested, &scene, &ray).is_none());
        }
        let inside = found(HitFault::PlanesInGridBox, &scene, &down(0.5, 0.9)).unwrap();
        assert_eq!((inside.t, inside.material), (6.0, 1));
        assert!(found(HitFault::PlanesInGridBox, &scene, &down(3.0, 0.0)).is_none());
        // n·P + d = 0: the floor at y = 1, over the sphere's top.
        let negated = found(HitFault::PlaneOffsetNegated, &scene, &down(3.0, 0.0)).unwrap();
        assert_eq!(
            (negated.t, negated.material, negated.normal),
            (4.0, 1, Vec3A::Y)
        );
        // The sphere as the course's.
        for fault in [
            HitFault::PlanesUntested,
            HitFault::PlanesInGridBox,
            HitFault::TriangleNormalTurned,
        ] {
            let hit = found(fault, &scene, &down(0.0, 0.0)).unwrap();
            assert_eq!((hit.t, hit.material), (4.0, 0));
        }
    }

    #[test]
    fn object_space_t_by_hand() {
        // A unit sphere scaled by 2 (the world's sphere of radius 2 about the origin), and a
        // small sphere of radius 0.5 at z = 4 in front of it.
        let scene = scene(
            "Group { numObjects 2
                 MaterialIndex 0 Transform { Scale 2 2 2 Sphere { center 0 0 0 radius 1 } }
                 MaterialIndex 1 Sphere { center 0 0 4 radius 0.5 } }",
        );
        let ray = Ray::new(Vec3A::new(0.0, 0.0, 10.0), -Vec3A::Z);
        // The course: the small sphere at t = 5.5 (the big one is at 8).
        assert_eq!(scene.world.intersect(&ray, 0.0).unwrap().t, 5.5);
        // In object space the ray's direction has length 0.5: made unit, the big sphere's hit
        // is at t = 8 × 0.5 = 4, which beats 5.5.
        let hit = found(HitFault::ObjectSpaceT(1.0), &scene, &ray).unwrap();
        assert_eq!((hit.t, hit.material, hit.normal), (4.0, 0, Vec3A::Z));
        // t_min bounds the measured t: from 4.5 on, the big sphere's far side is at 12 × 0.5 =
        // 6, and the small sphere's 5.5 wins.
        let later = HitFault::ObjectSpaceT(1.0)
            .found(&scene, &ray, 4.5, None)
            .unwrap();
        assert_eq!((later.t, later.material), (5.5, 1));
    }

    #[test]
    fn triangle_epsilons_by_hand() {
        // A triangle of legs 0.01 in the plane z = 0, above a plane at z = −1. For a ray
        // straight down the determinant of [a − b, a − c, d] is −1e-4.
        let scene = scene(
            "Group { numObjects 2
                 MaterialIndex 0 Triangle { vertex0 0 0 0 vertex1 0.01 0 0 vertex2 0 0.01 0 }
                 MaterialIndex 1 Plane { normal 0 0 1 offset -1 } }",
        );
        let down = |x: f32, y: f32| Ray::new(Vec3A::new(x, y, 10.0), -Vec3A::Z);
        let inside = down(0.001, 0.001);
        assert_eq!(
            cramer(
                &inside,
                &[
                    glam::Vec3::ZERO,
                    glam::Vec3::new(0.01, 0.0, 0.0),
                    glam::Vec3::new(0.0, 0.01, 0.0)
                ]
            )
            .0,
            -1e-4
        );
        let material = |fault, ray: &Ray| found(fault, &scene, ray).unwrap().material;
        assert_eq!(material(HitFault::DeterminantEpsilon(1e-5), &inside), 0);
        assert_eq!(material(HitFault::DeterminantEpsilon(1e-3), &inside), 1);
        // (0.001, 0.001) has β = γ = 0.1; (0.00005, 0.005) has β = 0.005, within 0.01 of the
        // edge γ's side.
        assert_eq!(material(HitFault::EdgeEpsilon(1e-2), &inside), 0);
        assert_eq!(
            material(HitFault::EdgeEpsilon(1e-2), &down(0.000_05, 0.005)),
            1
        );
        assert_eq!(
            material(HitFault::EdgeEpsilon(1e-3), &down(0.000_05, 0.005)),
            0
        );
    }

    #[test]
    fn a_grid_walk_that_trusts_its_first_hit() {
        // A slanted triangle whose box fills the grid's four cells along x, met by a ray along
        // +x at x = 3.5; a sphere at x = 2.5 in the third cell is nearer.
        let mut scene = scene(
            "Group { numObjects 2
                 MaterialIndex 0 Triangle { vertex0 0 3.5 -5 vertex1 0 3.5 5 vertex2 4 -0.5 0 }
                 MaterialIndex 1 Sphere { center 2.5 0 0 radius 0.4 } }",
        );
        scene.world.use_grid(UVec3::new(4, 1, 1)).unwrap();
        let ray = Ray::new(Vec3A::new(-1.0, 0.0, 0.0), Vec3A::X);
        let course = scene.world.intersect(&ray, 0.0).unwrap();
        assert_eq!((course.material, course.t), (1, 3.1));
        // The first cell lists the triangle, hit at t = 4.5 beyond the cell: trusted.
        let first = found(HitFault::FirstCellHit, &scene, &ray).unwrap();
        assert_eq!((first.material, first.t), (0, 4.5));
    }
}
