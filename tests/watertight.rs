//! Watertightness: a ray through a shared edge or vertex of a closed mesh never slips between
//! the triangles that share it.
//!
//! Closed meshes (every edge shared by exactly two triangles that use it in opposite directions)
//! are looked at from many random viewpoints, inside and outside:
//!
//! * From inside, a 32×32 picture is rendered through the library with `-shade_back` and a
//!   magenta background that the green material cannot produce: every pixel must show the mesh.
//! * From inside and outside, every camera ray is followed through the mesh, hit after hit
//!   (`World::intersect` with t_min just past the last hit): the crossings must alternate,
//!   entering then leaving, and a ray must end outside. A ray that slips through a crack either
//!   ends inside (it "escaped") or crosses the same way twice in a row. (Hits that cross the same
//!   way within a hair of each other count once: a ray through an edge may hit both triangles.)
//!   From outside, the picture is rendered too, and its background pixels must be exactly the
//!   rays that miss.
//! * From every viewpoint, rays are aimed exactly at vertices and at points of shared edges whose
//!   triangles all face the viewpoint the same way (so the ray must cross the surface there):
//!   the library must hit the surface at the aimed distance, and the watertight triangle test
//!   must hit at least one of the triangles around the vertex or edge.
//!
//! The meshes: the course's cube, bunny_200 and bunny_1k (closed), the cube under a Transform,
//! icospheres and UV spheres (with poles, where many triangles meet in one vertex) at several
//! scales and far from the origin, where f32 rounding is worst; and the 69k-triangle Stanford
//! bunny. The scan has five holes in its base (223 boundary edges), so it is not closed: it gets
//! only the aimed rays at its interior vertices and edges, and it is tested in full with its holes
//! capped (each hole's loop triangulated by ear clipping), which makes it closed.
//!
//! A plain Möller–Trumbore test with strict inequalities, run on the same aimed rays, does let
//! rays through (`moller_trumbore_leaks_on_the_same_rays`): the rays really probe the cracks.
//!
//! Inside viewpoints are found by a parity test in f64 (rays in three random directions from the
//! point all cross the surface an odd number of times), independent of the library. Everything is
//! seeded, so every run casts the same rays.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::Instant;

use glam::{DMat4, DVec3, Vec3, Vec3A};
use raycast::accel::World;
use raycast::camera::{Camera, pixel_to_screen};
use raycast::geometry::{Ray, intersect_triangle};
use raycast::parse::description::{CameraSpec, Projection};
use raycast::parse::obj::parse_obj;
use raycast::parse::parse_scene;
use raycast::render::render;
use raycast::{RenderSettings, Scene};
use rayon::prelude::*;

/// The side of the pictures rendered from each viewpoint.
const SIDE: u32 = 32;
const MAGENTA: [u8; 3] = [255, 0, 255];
/// Aimed rays per viewpoint: this many at vertices and as many at edges.
const AIMED_PER_KIND: usize = 8;

// ---------------------------------------------------------------------------------------------
// Random numbers: splitmix64, seeded per mesh.

struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit_f64()
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    fn in_cube(&mut self) -> DVec3 {
        DVec3::new(
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
        )
    }

    fn direction(&mut self) -> DVec3 {
        loop {
            let v = self.in_cube();
            let l = v.length_squared();
            if l > 1e-4 && l <= 1.0 {
                return v / l.sqrt();
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Meshes: the course's files, generated spheres, the capped bunny.

fn shared_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared")
}

/// Reads an .obj with the library's own reader, so the positions are exactly what it renders.
fn read_obj(name: &str, text: &[u8]) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mesh = parse_obj(Path::new(name), text).unwrap_or_else(|e| panic!("{name}: {e}"));
    (mesh.positions, mesh.triangles)
}

fn obj_text(positions: &[Vec3], triangles: &[[u32; 3]]) -> String {
    let mut text = String::new();
    // f32's Display is the shortest text that reads back as the same f32.
    for p in positions {
        writeln!(text, "v {} {} {}", p.x, p.y, p.z).unwrap();
    }
    for t in triangles {
        writeln!(text, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1).unwrap();
    }
    text
}

/// An icosahedron, each triangle split in four `level` times, pushed out onto the sphere.
fn icosphere(level: u32, centre: DVec3, radius: f64) -> String {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut unit: Vec<DVec3> = [
        [-1.0, g, 0.0],
        [1.0, g, 0.0],
        [-1.0, -g, 0.0],
        [1.0, -g, 0.0],
        [0.0, -1.0, g],
        [0.0, 1.0, g],
        [0.0, -1.0, -g],
        [0.0, 1.0, -g],
        [g, 0.0, -1.0],
        [g, 0.0, 1.0],
        [-g, 0.0, -1.0],
        [-g, 0.0, 1.0],
    ]
    .iter()
    .map(|&p| DVec3::from(p).normalize())
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut next = Vec::with_capacity(faces.len() * 4);
        for [a, b, c] in faces {
            let mut mid = |i: u32, j: u32| {
                *midpoints.entry((i.min(j), i.max(j))).or_insert_with(|| {
                    unit.push((unit[i as usize] + unit[j as usize]).normalize());
                    unit.len() as u32 - 1
                })
            };
            let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    let positions: Vec<Vec3> = unit
        .iter()
        .map(|&u| (centre + radius * u).as_vec3())
        .collect();
    obj_text(&positions, &faces)
}

/// A latitude-longitude sphere: `slices` triangles meet at each pole.
fn uv_sphere(slices: u32, stacks: u32, centre: DVec3, radius: f64) -> String {
    let mut unit = vec![DVec3::Z];
    for i in 1..stacks {
        let theta = std::f64::consts::PI * i as f64 / stacks as f64;
        for j in 0..slices {
            let phi = std::f64::consts::TAU * j as f64 / slices as f64;
            unit.push(DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ));
        }
    }
    unit.push(-DVec3::Z);
    let south = unit.len() as u32 - 1;
    let ring = |i: u32, j: u32| 1 + (i - 1) * slices + j % slices;
    let mut faces = Vec::new();
    for j in 0..slices {
        faces.push([0, ring(1, j), ring(1, j + 1)]);
        for i in 1..stacks - 1 {
            faces.push([ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)]);
            faces.push([ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)]);
        }
        faces.push([south, ring(stacks - 1, j + 1), ring(stacks - 1, j)]);
    }
    let positions: Vec<Vec3> = unit
        .iter()
        .map(|&u| (centre + radius * u).as_vec3())
        .collect();
    obj_text(&positions, &faces)
}

/// Who uses each edge, and what that says about the mesh.
struct Topology {
    /// The triangles around each vertex.
    faces_of: Vec<Vec<u32>>,
    /// Edges shared by exactly two triangles that use them in opposite directions.
    interior_edges: Vec<([u32; 2], [u32; 2])>,
    /// Edges used by one triangle only, in the direction that triangle uses them.
    boundary: Vec<[u32; 2]>,
    boundary_loops: Vec<Vec<u32>>,
    /// Edges of three or more triangles, or of two that use them the same way.
    bad_edges: usize,
    /// Triangles with a repeated vertex or zero area.
    degenerate: usize,
    unused_vertices: usize,
    /// Vertices on a boundary or bad edge: their triangles do not make a closed fan.
    open_vertex: Vec<bool>,
}

impl Topology {
    fn of(positions: &[DVec3], triangles: &[[u32; 3]]) -> Topology {
        let mut faces_of = vec![Vec::new(); positions.len()];
        let mut uses: HashMap<(u32, u32), Vec<(u32, bool)>> = HashMap::new();
        let mut degenerate = 0;
        for (f, &[a, b, c]) in triangles.iter().enumerate() {
            let [pa, pb, pc] = [a, b, c].map(|i| positions[i as usize]);
            if a == b || b == c || c == a || (pb - pa).cross(pc - pa) == DVec3::ZERO {
                degenerate += 1;
            }
            for (u, v) in [(a, b), (b, c), (c, a)] {
                uses.entry((u.min(v), u.max(v)))
                    .or_default()
                    .push((f as u32, u < v));
            }
            for i in [a, b, c] {
                faces_of[i as usize].push(f as u32);
            }
        }
        let mut interior_edges = Vec::new();
        let mut boundary = Vec::new();
        let mut bad_edges = 0;
        let mut open_vertex = vec![false; positions.len()];
        let mut keys: Vec<_> = uses.keys().copied().collect();
        keys.sort_unstable();
        for key in keys {
            let users = &uses[&key];
            match users[..] {
                [(f0, d0), (f1, d1)] if d0 != d1 => interior_edges.push(([key.0, key.1], [f0, f1])),
                [(_, forward)] => {
                    boundary.push(if forward {
                        [key.0, key.1]
                    } else {
                        [key.1, key.0]
                    });
                    open_vertex[key.0 as usize] = true;
                    open_vertex[key.1 as usize] = true;
                }
                _ => {
                    bad_edges += 1;
                    open_vertex[key.0 as usize] = true;
                    open_vertex[key.1 as usize] = true;
                }
            }
        }
        // Boundary loops: follow each boundary edge to the next.
        let next: HashMap<u32, u32> = boundary.iter().map(|&[u, v]| (u, v)).collect();
        let mut seen = std::collections::HashSet::new();
        let mut boundary_loops = Vec::new();
        for &[start, _] in &boundary {
            if seen.contains(&start) {
                continue;
            }
            let mut ring = Vec::new();
            let mut at = start;
            while seen.insert(at) {
                ring.push(at);
                at = next[&at];
            }
            boundary_loops.push(ring);
        }
        if next.len() != boundary.len() {
            // A vertex where two holes touch: the loops above are not simple.
            bad_edges += 1;
        }
        let unused_vertices = faces_of.iter().filter(|f| f.is_empty()).count();
        Topology {
            faces_of,
            interior_edges,
            boundary,
            boundary_loops,
            bad_edges,
            degenerate,
            unused_vertices,
            open_vertex,
        }
    }

    fn closed(&self) -> bool {
        self.boundary.is_empty() && self.bad_edges == 0 && self.degenerate == 0
    }
}

/// The mesh with each boundary loop closed by a triangulation of the loop (ear clipping, in
/// the plane that fits the loop best), so that the caps do not fold over themselves.
fn capped(positions: &[Vec3], triangles: &[[u32; 3]]) -> String {
    let topology = Topology::of(
        &positions.iter().map(|p| p.as_dvec3()).collect::<Vec<_>>(),
        triangles,
    );
    let mut triangles = triangles.to_vec();
    for ring in &topology.boundary_loops {
        // The mesh runs around the loop one way; its cap runs the other.
        let mut polygon: Vec<u32> = ring.iter().rev().copied().collect();
        let points: Vec<DVec3> = polygon
            .iter()
            .map(|&i| positions[i as usize].as_dvec3())
            .collect();
        // Newell's normal: the polygon runs counter-clockwise around it.
        let normal = (0..points.len())
            .map(|k| {
                let (a, b) = (points[k], points[(k + 1) % points.len()]);
                DVec3::new(
                    (a.y - b.y) * (a.z + b.z),
                    (a.z - b.z) * (a.x + b.x),
                    (a.x - b.x) * (a.y + b.y),
                )
            })
            .sum::<DVec3>()
            .normalize();
        let u = normal.any_orthonormal_vector();
        let v = normal.cross(u);
        let flat = |i: u32| {
            let p = positions[i as usize].as_dvec3();
            glam::DVec2::new(p.dot(u), p.dot(v))
        };
        let cross = |a: glam::DVec2, b: glam::DVec2, c: glam::DVec2| (b - a).perp_dot(c - a);
        while polygon.len() > 3 {
            let n = polygon.len();
            let corner = |k: usize| [polygon[(k + n - 1) % n], polygon[k], polygon[(k + 1) % n]];
            let is_ear = |k: usize| {
                let [a, b, c] = corner(k).map(flat);
                cross(a, b, c) > 0.0
                    && polygon.iter().all(|&i| {
                        corner(k).contains(&i) || {
                            let p = flat(i);
                            cross(a, b, p) < 0.0 || cross(b, c, p) < 0.0 || cross(c, a, p) < 0.0
                        }
                    })
            };
            // An ear if there is one; otherwise the most convex corner.
            let k = (0..n).find(|&k| is_ear(k)).unwrap_or_else(|| {
                (0..n)
                    .max_by(|&i, &j| {
                        let [a, b, c] = corner(i).map(flat);
                        let [d, e, f] = corner(j).map(flat);
                        cross(a, b, c).total_cmp(&cross(d, e, f))
                    })
                    .unwrap()
            });
            triangles.push(corner(k));
            polygon.remove(k);
        }
        triangles.push([polygon[0], polygon[1], polygon[2]]);
    }
    obj_text(positions, &triangles)
}

// ---------------------------------------------------------------------------------------------
// The cases: each mesh, how it is placed, and how many viewpoints it gets.

enum MeshFile {
    /// Under ../shared.
    Shared(&'static str),
    /// Under ../shared, with its holes capped.
    SharedCapped(&'static str),
    /// Generated .obj text, written to a temporary folder for the scene to load.
    Text(String),
}

struct Source {
    name: String,
    file: MeshFile,
    /// Transform ops around the mesh, as the scene file spells them.
    transform: Option<&'static str>,
    closed: bool,
    /// A point known to be strictly inside (object space): viewpoint 0, an axis-aligned camera,
    /// and rays aimed from it straight at vertices and edge midpoints.
    centre: Option<DVec3>,
    inside_views: usize,
    outside_views: usize,
}

fn sources() -> Vec<Source> {
    let course = |name: &str, file, transform, centre, views| Source {
        name: name.to_string(),
        file: MeshFile::Shared(file),
        transform,
        closed: true,
        centre,
        inside_views: views,
        outside_views: views,
    };
    let sphere = |name: String, text: String, centre: DVec3| Source {
        name,
        file: MeshFile::Text(text),
        transform: None,
        closed: true,
        centre: Some(centre),
        inside_views: 70,
        outside_views: 70,
    };
    let mut sources = vec![
        course(
            "cube.obj",
            "conformance/scenes/cube.obj",
            None,
            Some(DVec3::ZERO),
            100,
        ),
        course(
            "cube.obj under a Transform",
            "conformance/scenes/cube.obj",
            Some("Translate 10 -3 7 XRotate 30 YRotate -50 Scale 2.5 0.5 1"),
            Some(DVec3::ZERO),
            60,
        ),
        course(
            "bunny_200.obj",
            "conformance/scenes/bunny_200.obj",
            None,
            None,
            60,
        ),
        course(
            "bunny_1k.obj",
            "conformance/scenes/bunny_1k.obj",
            None,
            None,
            120,
        ),
        Source {
            file: MeshFile::SharedCapped("meshes/stanford-bunny.obj"),
            ..course(
                "stanford-bunny.obj, holes capped",
                "meshes/stanford-bunny.obj",
                None,
                None,
                120,
            )
        },
        Source {
            name: "stanford-bunny.obj (open: aimed rays only)".to_string(),
            file: MeshFile::Shared("meshes/stanford-bunny.obj"),
            transform: None,
            closed: false,
            centre: None,
            inside_views: 30,
            outside_views: 30,
        },
    ];
    let icospheres = [
        (0, DVec3::ZERO, 1.0),
        (2, DVec3::new(0.5, 0.25, -0.125), 1e-3),
        (3, DVec3::ZERO, 1e4),
        (4, DVec3::new(1000.0, -2000.0, 3000.0), 1.0),
    ];
    for (level, centre, radius) in icospheres {
        sources.push(sphere(
            format!("icosphere level {level}, radius {radius}, at {centre}"),
            icosphere(level, centre, radius),
            centre,
        ));
    }
    let uv_spheres = [
        (8, 4, DVec3::ZERO, 1.0),
        (64, 32, DVec3::new(3.0, -2.0, 1.0), 2.0),
        (256, 128, DVec3::new(100.0, 100.0, 100.0), 1.0),
        (32, 16, DVec3::new(-5000.0, 1000.0, 0.0), 10.0),
    ];
    for (slices, stacks, centre, radius) in uv_spheres {
        sources.push(sphere(
            format!("UV sphere {slices}x{stacks}, radius {radius}, at {centre}"),
            uv_sphere(slices, stacks, centre, radius),
            centre,
        ));
    }
    sources
}

/// A ray aimed at a vertex or at a point of an edge.
#[derive(Debug, Clone)]
struct Aimed {
    origin: Vec3,
    direction: Vec3,
    /// Where the ray crosses the triangles around the aimed point, worked out in f64.
    expect_t: f64,
    /// The triangles around the vertex or edge.
    around: Vec<u32>,
    at_vertex: bool,
}

impl Aimed {
    fn ray(&self) -> Ray {
        Ray::new(self.origin.into(), self.direction.into())
    }

    fn describe(&self) -> String {
        format!(
            "origin {:?} (bits {:08x?}) direction {:?} (bits {:08x?}), aimed {} at t {}",
            self.origin,
            self.origin.to_array().map(f32::to_bits),
            self.direction,
            self.direction.to_array().map(f32::to_bits),
            if self.at_vertex {
                "at a vertex"
            } else {
                "at an edge"
            },
            self.expect_t
        )
    }
}

struct View {
    inside: bool,
    camera: CameraSpec,
    aimed: Vec<Aimed>,
}

/// A mesh ready for testing: its triangles as the library holds them, in world space for the
/// tests' own geometry, and its viewpoints.
struct Case {
    name: String,
    /// The scene file's object, with `{obj}` for the mesh file.
    object: String,
    /// The .obj text, or the shared file.
    file: Result<String, PathBuf>,
    closed: bool,
    /// True when no Transform: the library's triangles are `triangles` of `positions`.
    world_space: bool,
    positions: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    /// +1 when the triangles are counter-clockwise seen from outside, -1 otherwise.
    orientation: f32,
    views: Vec<View>,
}

impl Case {
    fn triangle(&self, f: u32) -> [Vec3; 3] {
        self.triangles[f as usize].map(|i| self.positions[i as usize])
    }
}

struct Workload {
    cases: Vec<Case>,
    /// Meshes left out because ../shared is missing.
    skipped: Vec<String>,
}

fn workload() -> &'static Workload {
    static WORKLOAD: OnceLock<Workload> = OnceLock::new();
    WORKLOAD.get_or_init(|| {
        let start = Instant::now();
        let mut cases = Vec::new();
        let mut skipped = Vec::new();
        for (index, source) in sources().into_iter().enumerate() {
            match prepare(index as u64, source) {
                Ok(case) => cases.push(case),
                Err(name) => skipped.push(name),
            }
        }
        if !skipped.is_empty() {
            eprintln!(
                "\n*** WATERTIGHT: no course data at {}; skipped {} ***\n",
                shared_dir().display(),
                skipped.join(", ")
            );
        }
        eprintln!("watertight: viewpoints chosen in {:.2?}", start.elapsed());
        Workload { cases, skipped }
    })
}

fn object_text(transform: Option<&str>) -> String {
    let mesh = "TriangleMesh { obj_file {obj} }";
    match transform {
        Some(ops) => format!("Transform {{ {ops} {mesh} }}"),
        None => mesh.to_string(),
    }
}

fn scene_text(object: &str, obj: &str) -> String {
    format!(
        "PerspectiveCamera {{ center 0 0 10 direction 0 0 -1 up 0 1 0 angle 60 }}\n\
         Lights {{ numLights 1 DirectionalLight {{ direction -0.3 -0.5 -1 color 0.7 0.7 0.7 }} }}\n\
         Background {{ color 1 0 1 ambientLight 0.2 0.2 0.2 }}\n\
         Materials {{ numMaterials 1 Material {{ diffuseColor 0 1 0 }} }}\n\
         Group {{ numObjects 1 MaterialIndex 0 {} }}\n",
        object.replace("{obj}", obj)
    )
}

fn prepare(seed: u64, source: Source) -> Result<Case, String> {
    let (name, text, file) = match &source.file {
        MeshFile::Shared(relative) | MeshFile::SharedCapped(relative) => {
            let path = shared_dir().join(relative);
            let Ok(bytes) = std::fs::read(&path) else {
                return Err(source.name);
            };
            if let MeshFile::SharedCapped(_) = source.file {
                let (positions, triangles) = read_obj(relative, &bytes);
                let text = capped(&positions, &triangles);
                (*relative, text.clone().into_bytes(), Ok(text))
            } else {
                (*relative, bytes, Err(path))
            }
        }
        MeshFile::Text(text) => ("generated", text.clone().into_bytes(), Ok(text.clone())),
    };
    let (positions, triangles) = read_obj(name, &text);
    let object = object_text(source.transform);
    // The placement, exactly as the library reads it.
    let description = parse_scene(Path::new("case.txt"), &scene_text(&object, "m.obj")).unwrap();
    let matrix = description.transforms.first().copied();
    let world: Vec<DVec3> = positions
        .iter()
        .map(|p| {
            let p = p.as_dvec3();
            matrix.map_or(p, |m: DMat4| m.transform_point3(p))
        })
        .collect();
    let topology = Topology::of(&world, &triangles);
    if source.closed {
        assert!(
            topology.closed(),
            "{}: not closed: {} boundary edges, {} bad edges, {} degenerate triangles",
            source.name,
            topology.boundary.len(),
            topology.bad_edges,
            topology.degenerate
        );
    }
    let tris: Vec<[DVec3; 3]> = triangles
        .iter()
        .map(|t| t.map(|i| world[i as usize]))
        .collect();
    let (centre, radius) = bounding_sphere(&world, &triangles);
    // The sign of the enclosed volume: which way the triangles face.
    let volume: f64 = tris
        .iter()
        .map(|[a, b, c]| (*a - centre).dot((*b - centre).cross(*c - centre)))
        .sum();
    let orientation = if volume >= 0.0 { 1.0 } else { -1.0 };
    // Unit normals that point out of the mesh.
    let normals: Vec<DVec3> = tris
        .iter()
        .map(|[a, b, c]| (*b - *a).cross(*c - *a).normalize_or_zero() * orientation)
        .collect();

    let mut rng = Rng(0x5EED_0000 + seed * 0x1_0000_0001);
    let points = viewpoints(&mut rng, &source, &tris, centre, radius, matrix);
    let geometry = Geometry {
        world_space: matrix.is_none(),
        matrix: matrix.unwrap_or(DMat4::IDENTITY),
        positions: &positions,
        triangles: &triangles,
        topology: &topology,
        normals: &normals,
    };
    let mut views = Vec::new();
    for (k, &(point, inside)) in points.iter().enumerate() {
        let at_centre = k == 0 && source.centre.is_some();
        let camera = if at_centre {
            CameraSpec {
                center: point,
                direction: Vec3::Z,
                up: Vec3::Y,
                projection: Projection::Perspective { angle: 90.0 },
            }
        } else if inside {
            let angle = rng.range(30.0, 170.0);
            random_camera(&mut rng, point, None, angle)
        } else {
            let d = (centre - point.as_dvec3()).length();
            let angle = if d > 1.05 * radius {
                (2.0 * (radius / d).asin().to_degrees() * 1.15).clamp(5.0, 150.0)
            } else {
                rng.range(60.0, 150.0)
            };
            let look_at = centre + 0.3 * radius * rng.in_cube();
            random_camera(&mut rng, point, Some(look_at), angle)
        };
        let mut aimed = Vec::new();
        if at_centre {
            aimed.extend(geometry.aim_at_everything(point));
        }
        for at_vertex in [true, false] {
            let mut found = 0;
            for attempt in 0..64 {
                if found == AIMED_PER_KIND {
                    break;
                }
                if let Some(a) = geometry.aim(&mut rng, point, at_vertex, attempt % 2 == 0) {
                    aimed.push(a);
                    found += 1;
                }
            }
        }
        views.push(View {
            inside,
            camera,
            aimed,
        });
    }
    Ok(Case {
        name: source.name,
        object,
        file,
        closed: source.closed,
        world_space: matrix.is_none(),
        positions,
        triangles,
        orientation: orientation as f32,
        views,
    })
}

fn random_camera(rng: &mut Rng, center: Vec3, look_at: Option<DVec3>, angle: f64) -> CameraSpec {
    let direction = match look_at {
        Some(target) => (target - center.as_dvec3()).normalize(),
        None => rng.direction(),
    };
    let up = loop {
        let up = rng.direction();
        if up.cross(direction).length() > 0.2 {
            break up;
        }
    };
    CameraSpec {
        center,
        direction: direction.as_vec3(),
        up: up.as_vec3(),
        projection: Projection::Perspective {
            angle: angle as f32,
        },
    }
}

/// The centre of the vertices' box and the distance to the farthest used vertex.
fn bounding_sphere(world: &[DVec3], triangles: &[[u32; 3]]) -> (DVec3, f64) {
    let used = || triangles.iter().flatten().map(|&i| world[i as usize]);
    let (lo, hi) = used().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    );
    let centre = 0.5 * (lo + hi);
    let radius = used().map(|p| (p - centre).length()).fold(0.0, f64::max);
    (centre, radius)
}

/// Viewpoints (rounded to f32, as the camera takes them) and whether each is inside: first the
/// centre if known, then points of the box around the mesh sorted by a parity test, then points
/// on a shell around it. Every point keeps a little distance from the surface.
fn viewpoints(
    rng: &mut Rng,
    source: &Source,
    tris: &[[DVec3; 3]],
    centre: DVec3,
    radius: f64,
    matrix: Option<DMat4>,
) -> Vec<(Vec3, bool)> {
    let clearance = 1e-3 * radius;
    let mut inside = Vec::new();
    let mut outside = Vec::new();
    if let Some(c) = source.centre {
        let c = matrix.map_or(c, |m| m.transform_point3(c)).as_vec3();
        assert_eq!(
            classify(&mut Rng(1), c.as_dvec3(), tris, clearance),
            Some(true),
            "{}: the centre is not inside",
            source.name
        );
        inside.push(c);
    }
    let (lo, hi) = tris.iter().flatten().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let (mid, half) = (0.5 * (lo + hi), 0.6 * (hi - lo));
    let outside_in_box = source.outside_views / 2;
    let mut batches = 0;
    while inside.len() < source.inside_views || outside.len() < outside_in_box {
        batches += 1;
        assert!(
            batches < 100,
            "{}: cannot find viewpoints ({} inside, {} outside)",
            source.name,
            inside.len(),
            outside.len()
        );
        let candidates: Vec<(Vec3, u64)> = (0..64)
            .map(|_| ((mid + half * rng.in_cube()).as_vec3(), rng.next_u64()))
            .collect();
        let classes: Vec<Option<bool>> = candidates
            .par_iter()
            .map(|&(p, seed)| {
                if source.closed {
                    classify(&mut Rng(seed), p.as_dvec3(), tris, clearance)
                } else {
                    // An open mesh has no inside: any point clear of the surface will do.
                    far_from(p.as_dvec3(), tris, clearance).then_some(seed % 2 == 0)
                }
            })
            .collect();
        for (&(p, _), class) in candidates.iter().zip(classes) {
            match class {
                Some(true) if inside.len() < source.inside_views => inside.push(p),
                Some(false) if outside.len() < outside_in_box => outside.push(p),
                _ => {}
            }
        }
    }
    while outside.len() < source.outside_views {
        let d = rng.range(1.2, 4.0) * radius;
        outside.push((centre + d * rng.direction()).as_vec3());
    }
    let mut points: Vec<(Vec3, bool)> = inside.into_iter().map(|p| (p, true)).collect();
    points.extend(outside.into_iter().map(|p| (p, false)));
    points
}

/// Inside (Some(true)) when rays in three random directions all cross the surface an odd number
/// of times, outside when all even; None when they disagree, when one passes too near an edge to
/// tell, or when the point is too near the surface.
fn classify(rng: &mut Rng, p: DVec3, tris: &[[DVec3; 3]], clearance: f64) -> Option<bool> {
    let mut parity = None;
    for _ in 0..3 {
        let odd = crossings(p, rng.direction(), tris)? % 2 == 1;
        if parity.is_some_and(|was| was != odd) {
            return None;
        }
        parity = Some(odd);
    }
    far_from(p, tris, clearance).then_some(parity?)
}

/// Möller–Trumbore in f64, refusing (None) rays that pass within a hair of an edge.
fn crossings(o: DVec3, d: DVec3, tris: &[[DVec3; 3]]) -> Option<usize> {
    const EPS: f64 = 1e-7;
    let mut n = 0;
    for [a, b, c] in tris {
        let (e1, e2) = (*b - *a, *c - *a);
        let p = d.cross(e2);
        let det = e1.dot(p);
        if det.abs() <= 1e-9 * e1.length() * e2.length() {
            continue;
        }
        let s = o - *a;
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let v = d.dot(q) / det;
        let t = e2.dot(q) / det;
        if t <= 0.0 || u < -EPS || v < -EPS || u + v > 1.0 + EPS {
            continue;
        }
        if u < EPS || v < EPS || u + v > 1.0 - EPS {
            return None;
        }
        n += 1;
    }
    Some(n)
}

fn far_from(p: DVec3, tris: &[[DVec3; 3]], clearance: f64) -> bool {
    tris.iter().all(|t| distance_to_triangle(p, t) > clearance)
}

/// Ericson, Real-Time Collision Detection, 5.1.5.
fn distance_to_triangle(p: DVec3, [a, b, c]: &[DVec3; 3]) -> f64 {
    let (a, b, c) = (*a, *b, *c);
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.length();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp.length();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (p - (a + d1 / (d1 - d3) * ab)).length();
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp.length();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (p - (a + d2 / (d2 - d6) * ac)).length();
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (p - (b + w * (c - b))).length();
    }
    let denom = 1.0 / (va + vb + vc);
    (p - (a + ab * (vb * denom) + ac * (vc * denom))).length()
}

/// What aiming needs to know about a mesh.
struct Geometry<'a> {
    world_space: bool,
    matrix: DMat4,
    /// Object space, as the library holds them.
    positions: &'a [Vec3],
    triangles: &'a [[u32; 3]],
    topology: &'a Topology,
    /// World space, pointing out.
    normals: &'a [DVec3],
}

impl Geometry<'_> {
    /// A ray from `origin` at a random vertex or point of an edge, if the triangles there all
    /// face the origin the same way, clearly (otherwise the ray may graze the surface there).
    fn aim(&self, rng: &mut Rng, origin: Vec3, at_vertex: bool, unit: bool) -> Option<Aimed> {
        let t = self.topology;
        if at_vertex {
            let v = rng.below(self.positions.len());
            if t.open_vertex[v] || t.faces_of[v].is_empty() {
                return None;
            }
            self.aim_at(origin, self.positions[v], &t.faces_of[v], true, unit)
        } else {
            if t.interior_edges.is_empty() {
                return None;
            }
            let ([a, b], faces) = t.interior_edges[rng.below(t.interior_edges.len())];
            let (a, b) = (self.positions[a as usize], self.positions[b as usize]);
            let point = if rng.below(2) == 0 {
                (a + b) * 0.5
            } else {
                // Clear of the ends, where rounding could carry the point into a third triangle.
                a + rng.range(0.1, 0.9) as f32 * (b - a)
            };
            self.aim_at(origin, point, &faces, false, unit)
        }
    }

    /// From a point of the mesh's inside, straight at every vertex (if at most 64) and every edge
    /// midpoint (if at most 200), and at every vertex where more than six triangles meet (the UV
    /// spheres' poles: from the centre, the ray runs exactly along an axis through the pole).
    fn aim_at_everything(&self, origin: Vec3) -> Vec<Aimed> {
        let t = self.topology;
        let mut aimed = Vec::new();
        let n = self.positions.len();
        let vertices: Vec<usize> = (0..n)
            .filter(|&v| n <= 64 || t.faces_of[v].len() > 6)
            .collect();
        for v in vertices {
            aimed.extend(self.aim_at(origin, self.positions[v], &t.faces_of[v], true, v % 2 == 0));
        }
        if t.interior_edges.len() <= 200 {
            for (k, &([a, b], faces)) in t.interior_edges.iter().enumerate() {
                let point = (self.positions[a as usize] + self.positions[b as usize]) * 0.5;
                aimed.extend(self.aim_at(origin, point, &faces, false, k % 2 == 0));
            }
        }
        aimed
    }

    fn aim_at(
        &self,
        origin: Vec3,
        point: Vec3,
        around: &[u32],
        at_vertex: bool,
        unit: bool,
    ) -> Option<Aimed> {
        let world = |p: Vec3| {
            let p = p.as_dvec3();
            if self.world_space {
                p
            } else {
                self.matrix.transform_point3(p)
            }
        };
        let target = world(point).as_vec3();
        let to = target.as_dvec3() - origin.as_dvec3();
        let distance = to.length();
        let cosines: Vec<f64> = around
            .iter()
            .map(|&f| self.normals[f as usize].dot(to) / distance)
            .collect();
        let clear = cosines.iter().all(|&c| c > 0.02) || cosines.iter().all(|&c| c < -0.02);
        if !clear || distance == 0.0 {
            return None;
        }
        let mut direction = target - origin;
        if unit {
            direction = direction.normalize();
        }
        // Where the ray, as rounded to f32, crosses the triangles around the point, in f64: the
        // most central crossing. Rounding the aimed point to f32 moves it off the edge by an
        // ulp or so, which may be more than the surface's own size allows near an end of it.
        let (o, d) = (origin.as_dvec3(), direction.as_dvec3());
        let (_, expect_t) = around
            .iter()
            .filter_map(|&f| {
                let [a, b, c] = self.topology_triangle(f).map(world);
                barycentric_hit(o, d, [a, b, c])
            })
            .max_by(|x, y| x.0.total_cmp(&y.0))?;
        Some(Aimed {
            origin,
            direction,
            expect_t,
            around: around.to_vec(),
            at_vertex,
        })
    }

    fn topology_triangle(&self, f: u32) -> [Vec3; 3] {
        self.triangles[f as usize].map(|i| self.positions[i as usize])
    }
}

/// The ray's crossing with the triangle in f64, if it passes through it or within a hair of
/// its edges: the smallest barycentric coordinate and t.
fn barycentric_hit(o: DVec3, d: DVec3, [a, b, c]: [DVec3; 3]) -> Option<(f64, f64)> {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 {
        return None;
    }
    let s = o - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    let t = e2.dot(q) / det;
    let least = u.min(v).min(1.0 - u - v);
    (least >= -1e-9 && t > 0.0).then_some((least, t))
}

// ---------------------------------------------------------------------------------------------
// Following a ray through the mesh.

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Outcome {
    Fine,
    /// The ray ended inside: it left through a crack.
    Escaped,
    /// Two crossings the same way in a row: one in between was missed.
    Disorder,
}

/// Follows the ray hit after hit. Hits that cross the same way within a hair of each other are
/// one crossing (a ray through a shared edge may hit both triangles).
fn trace(world: &World, ray: &Ray, mut t_min: f32, inside: bool, orientation: f32) -> Outcome {
    let mut depth = i32::from(inside);
    let mut last: Option<(f32, bool)> = None;
    for _ in 0..10_000 {
        let Some(hit) = world.intersect(ray, t_min) else {
            return if depth == 0 {
                Outcome::Fine
            } else {
                Outcome::Escaped
            };
        };
        let entering = ray.direction.dot(hit.normal) * orientation < 0.0;
        let same_crossing = last.is_some_and(|(t, was_entering)| {
            was_entering == entering && hit.t - t <= 1e-5 * t.abs()
        });
        if !same_crossing {
            depth += if entering { 1 } else { -1 };
            if depth < 0 {
                return Outcome::Disorder;
            }
        }
        last = Some((hit.t, entering));
        t_min = hit.t.next_up();
    }
    Outcome::Disorder
}

#[derive(Debug, Default, Clone, Copy)]
struct Tally {
    inside_views: usize,
    outside_views: usize,
    aimed_only_views: usize,
    camera_rays: usize,
    aimed_rays: usize,
    escaped: usize,
    disorder: usize,
    /// Aimed rays whose hit is not at the aimed point.
    off_target: usize,
    /// Aimed rays that the watertight test lets through all the triangles around the point.
    slipped: usize,
    /// Background pixels seen from outside: the check of the background colour means something.
    outside_background: usize,
    /// Pixels from outside that are background where the ray hits, or the other way round.
    render_mismatch: usize,
}

impl std::ops::AddAssign for Tally {
    fn add_assign(&mut self, o: Tally) {
        self.inside_views += o.inside_views;
        self.outside_views += o.outside_views;
        self.aimed_only_views += o.aimed_only_views;
        self.camera_rays += o.camera_rays;
        self.aimed_rays += o.aimed_rays;
        self.escaped += o.escaped;
        self.disorder += o.disorder;
        self.off_target += o.off_target;
        self.slipped += o.slipped;
        self.outside_background += o.outside_background;
        self.render_mismatch += o.render_mismatch;
    }
}

impl Tally {
    fn failures(&self) -> usize {
        self.escaped + self.disorder + self.off_target + self.slipped + self.render_mismatch
    }
}

fn describe_ray(ray: &Ray) -> String {
    let o: Vec3 = ray.origin.into();
    let d: Vec3 = ray.direction.into();
    format!(
        "origin {o:?} (bits {:08x?}) direction {d:?} (bits {:08x?})",
        o.to_array().map(f32::to_bits),
        d.to_array().map(f32::to_bits)
    )
}

fn build_scene(index: usize, case: &Case, folder: &Path) -> Scene {
    let obj = match &case.file {
        Ok(text) => {
            let path = folder.join(format!("mesh{index}.obj"));
            std::fs::write(&path, text).unwrap();
            path
        }
        Err(path) => path.clone(),
    };
    let text = scene_text(&case.object, obj.to_str().unwrap());
    let description = parse_scene(Path::new("watertight.txt"), &text).unwrap();
    Scene::from_description(&description).unwrap()
}

fn check_case(index: usize, case: &Case, folder: &Path, failures: &mut Vec<String>) -> Tally {
    let mut scene = build_scene(index, case, folder);
    let mut tally = Tally::default();
    let settings = RenderSettings {
        width: SIDE,
        height: SIDE,
        colour: true,
        normals: false,
        depth: None,
        trace: raycast::trace::TraceSettings {
            shade_back: true,
            ..Default::default()
        },
        progress: false,
        counter: None,
        stop: None,
        sampling: Default::default(),
        keep_film: false,
    };
    let fail = |failures: &mut Vec<String>, what: String| {
        if failures
            .iter()
            .filter(|f: &&String| f.starts_with(&case.name))
            .count()
            < 6
        {
            failures.push(format!("{}: {what}", case.name));
        }
    };
    for view in &case.views {
        scene.camera = Camera::new(&view.camera);
        if case.closed {
            if view.inside {
                tally.inside_views += 1;
            } else {
                tally.outside_views += 1;
            }
            let picture = render(&scene, &settings).colour.unwrap();
            let scene = &scene;
            let outcomes: Vec<(Outcome, bool, Ray)> = (0..SIDE * SIDE)
                .into_par_iter()
                .map(|index| {
                    let (row, column) = (index / SIDE, index % SIDE);
                    let (u, v) = pixel_to_screen(column, SIDE - 1 - row, SIDE, SIDE);
                    let ray = scene.camera.ray(u, v);
                    let t_min = scene.camera.t_min();
                    let outcome = trace(&scene.world, &ray, t_min, view.inside, case.orientation);
                    (outcome, scene.world.intersect(&ray, t_min).is_some(), ray)
                })
                .collect();
            for ((outcome, hit, ray), pixel) in outcomes.into_iter().zip(&picture.pixels) {
                tally.camera_rays += 1;
                let background = *pixel == MAGENTA;
                if !view.inside {
                    tally.outside_background += usize::from(background);
                    if background == hit {
                        tally.render_mismatch += 1;
                        fail(
                            failures,
                            format!("pixel disagrees with intersect: {}", describe_ray(&ray)),
                        );
                    }
                }
                if (view.inside && background) || outcome == Outcome::Escaped {
                    tally.escaped += 1;
                    let how = if background {
                        "background pixel"
                    } else {
                        "ended inside"
                    };
                    fail(
                        failures,
                        format!("camera ray escaped ({how}): {}", describe_ray(&ray)),
                    );
                } else if outcome == Outcome::Disorder {
                    tally.disorder += 1;
                    fail(
                        failures,
                        format!("camera ray crossed out of order: {}", describe_ray(&ray)),
                    );
                }
            }
        } else {
            tally.aimed_only_views += 1;
        }
        for aimed in &view.aimed {
            tally.aimed_rays += 1;
            let ray = aimed.ray();
            if case.closed {
                match trace(&scene.world, &ray, 0.0, view.inside, case.orientation) {
                    Outcome::Fine => {}
                    Outcome::Escaped => {
                        tally.escaped += 1;
                        fail(failures, format!("aimed ray escaped: {}", aimed.describe()));
                    }
                    Outcome::Disorder => {
                        tally.disorder += 1;
                        fail(
                            failures,
                            format!("aimed ray out of order: {}", aimed.describe()),
                        );
                    }
                }
            }
            // The surface is there, at the aimed distance (whatever lies in front of it).
            let tolerance = 1e-4 * aimed.expect_t;
            let hit = scene
                .world
                .intersect(&ray, (aimed.expect_t - tolerance) as f32);
            if !hit.is_some_and(|h| (h.t as f64 - aimed.expect_t).abs() <= tolerance) {
                tally.off_target += 1;
                fail(
                    failures,
                    format!(
                        "aimed ray hit {:?} instead: {}",
                        hit.map(|h| h.t),
                        aimed.describe()
                    ),
                );
            }
            // And the triangle test itself hits at least one triangle around the point.
            if case.world_space {
                let hits = aimed
                    .around
                    .iter()
                    .filter(|&&f| {
                        intersect_triangle(&ray, &case.triangle(f), 0.0, f32::INFINITY).is_some()
                    })
                    .count();
                if hits == 0 {
                    tally.slipped += 1;
                    fail(failures, format!("aimed ray slipped: {}", aimed.describe()));
                }
            }
        }
    }
    tally
}

// ---------------------------------------------------------------------------------------------
// The tests.

#[test]
fn no_ray_slips_through_a_closed_mesh() {
    let start = Instant::now();
    let workload = workload();
    let folder = tempfile::tempdir().unwrap();
    let mut total = Tally::default();
    let mut failures = Vec::new();
    for (index, case) in workload.cases.iter().enumerate() {
        let case_start = Instant::now();
        let tally = check_case(index, case, folder.path(), &mut failures);
        eprintln!(
            "  {:<55} {:>6} triangles {:>4} views {:>7} rays {:>3} failures  {:.2?}",
            case.name,
            case.triangles.len(),
            tally.inside_views + tally.outside_views + tally.aimed_only_views,
            tally.camera_rays + tally.aimed_rays,
            tally.failures(),
            case_start.elapsed()
        );
        total += tally;
    }
    let views = total.inside_views + total.outside_views + total.aimed_only_views;
    let rays = total.camera_rays + total.aimed_rays;
    // Straight to stderr, past the test harness's capture: CI logs show the count.
    let _ = writeln!(
        std::io::stderr(),
        "watertight: {views} views ({} inside, {} outside, {} of the open bunny), {rays} rays \
         ({} aimed at vertices and edges), {} escaped, {} crossed out of order, {} aimed off \
         target, {} slipped between triangles, in {:.2?}",
        total.inside_views,
        total.outside_views,
        total.aimed_only_views,
        total.aimed_rays,
        total.escaped,
        total.disorder,
        total.off_target,
        total.slipped,
        start.elapsed()
    );
    for failure in &failures {
        println!("  {failure}");
    }
    assert_eq!(total.escaped, 0, "rays escaped from closed meshes");
    assert_eq!(total.disorder, 0, "rays crossed a closed mesh out of order");
    assert_eq!(total.off_target, 0, "aimed rays missed the aimed point");
    assert_eq!(total.slipped, 0, "aimed rays slipped between triangles");
    assert_eq!(
        total.render_mismatch, 0,
        "pictures disagree with World::intersect"
    );
    assert!(
        total.outside_background > 0,
        "no background seen from outside"
    );
    if workload.skipped.is_empty() {
        assert!(total.inside_views >= 1000 && total.outside_views >= 1000);
    }
}

/// A plain Möller–Trumbore test with strict inequalities: not watertight.
fn moller_trumbore(origin: Vec3, direction: Vec3, [a, b, c]: [Vec3; 3]) -> Option<f32> {
    let (e1, e2) = (b - a, c - a);
    let p = direction.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - a;
    let u = s.dot(p) * inv;
    if u <= 0.0 || u >= 1.0 {
        return None;
    }
    let q = s.cross(e1);
    let v = direction.dot(q) * inv;
    if v <= 0.0 || u + v >= 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t > 0.0).then_some(t)
}

/// The aimed rays do probe the cracks: a test that is not watertight lets some of them through
/// all the triangles around the vertex or edge they are aimed at, where the library's test
/// (checked in the main test, and here again) never does.
#[test]
fn moller_trumbore_leaks_on_the_same_rays() {
    let workload = workload();
    let (mut rays, mut leaks, mut at_vertices, mut watertight_leaks) = (0, 0, 0, 0);
    let mut example = None;
    for case in workload.cases.iter().filter(|c| c.world_space) {
        let mut case_leaks = 0;
        for aimed in case.views.iter().flat_map(|v| &v.aimed) {
            rays += 1;
            let triangles = aimed.around.iter().map(|&f| case.triangle(f));
            if triangles
                .clone()
                .all(|t| moller_trumbore(aimed.origin, aimed.direction, t).is_none())
            {
                leaks += 1;
                case_leaks += 1;
                at_vertices += usize::from(aimed.at_vertex);
                example.get_or_insert_with(|| format!("{}: {}", case.name, aimed.describe()));
            }
            let ray = aimed.ray();
            if triangles
                .clone()
                .all(|t| intersect_triangle(&ray, &t, 0.0, f32::INFINITY).is_none())
            {
                watertight_leaks += 1;
            }
        }
        eprintln!("  Möller–Trumbore: {case_leaks:>4} leaks on {}", case.name);
    }
    println!(
        "moller-trumbore: {leaks} of {rays} aimed rays leak ({at_vertices} at vertices, {} at \
         edges); watertight test: {watertight_leaks}",
        leaks - at_vertices
    );
    if let Some(example) = example {
        println!("  for example {example}");
    }
    assert!(
        leaks > 0,
        "the aimed rays never find a crack in a non-watertight test"
    );
    assert_eq!(watertight_leaks, 0);
}

/// Which meshes are closed, as the main test relies on.
#[test]
fn course_meshes_are_closed_and_the_scanned_bunny_is_not() {
    let shared = shared_dir();
    let read = |relative: &str| {
        let bytes = std::fs::read(shared.join(relative)).ok()?;
        let (positions, triangles) = read_obj(relative, &bytes);
        Some((positions, triangles))
    };
    let topology = |(positions, triangles): &(Vec<Vec3>, Vec<[u32; 3]>)| {
        let world: Vec<DVec3> = positions.iter().map(|p| p.as_dvec3()).collect();
        Topology::of(&world, triangles)
    };
    for name in ["cube.obj", "bunny_200.obj", "bunny_1k.obj"] {
        let Some(mesh) = read(&format!("conformance/scenes/{name}")) else {
            eprintln!(
                "*** {name} missing under {}: not checked ***",
                shared.display()
            );
            continue;
        };
        let t = topology(&mesh);
        assert!(t.closed(), "{name} is not closed");
        assert_eq!(t.unused_vertices, 0, "{name}");
    }
    let Some(bunny) = read("meshes/stanford-bunny.obj") else {
        eprintln!("*** stanford-bunny.obj missing: not checked ***");
        return;
    };
    let t = topology(&bunny);
    // The scan's base has five holes; the file also lists 1113 vertices no triangle uses.
    assert!(!t.closed());
    assert_eq!(t.boundary.len(), 223);
    let mut loops: Vec<usize> = t.boundary_loops.iter().map(Vec::len).collect();
    loops.sort_unstable();
    assert_eq!(loops, [22, 39, 40, 42, 80]);
    assert_eq!((t.bad_edges, t.degenerate, t.unused_vertices), (0, 0, 1113));
    let capped = read_obj("capped", capped(&bunny.0, &bunny.1).as_bytes());
    assert!(topology(&capped).closed());
}

#[test]
fn generated_spheres_are_closed_and_face_out() {
    for source in sources() {
        let MeshFile::Text(text) = &source.file else {
            continue;
        };
        let (positions, triangles) = read_obj(&source.name, text.as_bytes());
        let world: Vec<DVec3> = positions.iter().map(|p| p.as_dvec3()).collect();
        assert!(Topology::of(&world, &triangles).closed(), "{}", source.name);
        let centre = source.centre.unwrap();
        let volume: f64 = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| world[i as usize] - centre);
                a.dot(b.cross(c))
            })
            .sum();
        assert!(volume > 0.0, "{} faces inward", source.name);
    }
}

#[test]
fn a_ray_exactly_through_a_uv_pole_hits() {
    // The hard case by construction: the ray runs exactly through the vertex that 256
    // triangles share, from the centre and from outside.
    let (positions, triangles) = read_obj(
        "uv",
        uv_sphere(256, 128, DVec3::new(100.0, 100.0, 100.0), 1.0).as_bytes(),
    );
    let centre = Vec3::splat(100.0);
    let pole = positions[0];
    assert_eq!((pole.x, pole.y), (centre.x, centre.y));
    let fan: Vec<[Vec3; 3]> = triangles
        .iter()
        .filter(|t| t.contains(&0))
        .map(|t| t.map(|i| positions[i as usize]))
        .collect();
    assert_eq!(fan.len(), 256);
    for (origin, direction) in [
        (centre, Vec3::Z),
        (centre + Vec3::new(0.0, 0.0, 5.0), -Vec3::Z),
        (centre, pole - centre),
    ] {
        let ray = Ray::new(Vec3A::from(origin), Vec3A::from(direction));
        let hits = fan
            .iter()
            .filter(|t| intersect_triangle(&ray, t, 0.0, f32::INFINITY).is_some())
            .count();
        assert!(hits >= 1, "a ray through the pole slipped through its fan");
    }
}
