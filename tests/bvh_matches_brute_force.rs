//! Property tests: the BVHs (top level and per mesh, through nested transforms and shared mesh
//! instances), and the course's uniform grid, find exactly the hit that testing every primitive
//! finds, and the same answer to shadow rays; a packet of rays searched together finds exactly
//! what each of its rays finds alone.

use std::fmt::Write;
use std::path::Path;

use glam::Vec3A;
use proptest::prelude::*;
use raycast::Scene;
use raycast::geometry::Ray;
use raycast::parse::parse_scene;

mod common;

/// An object of the generated scene: the tree the file spells out.
#[derive(Debug, Clone)]
enum Node {
    Sphere([f32; 3], f32),
    Triangle([[f32; 3]; 3]),
    /// One of the two mesh files, placed.
    Mesh(usize),
    /// A tilted floor below everything else.
    Plane,
    Transform(Vec<Op>, Box<Node>),
    Group(Vec<(u32, Node)>),
}

#[derive(Debug, Clone)]
enum Op {
    Translate([f32; 3]),
    Scale([f32; 3]),
    Rotate(usize, f32),
}

fn coordinate() -> impl Strategy<Value = f32> {
    -4.0f32..4.0
}

fn point() -> impl Strategy<Value = [f32; 3]> {
    [coordinate(), coordinate(), coordinate()]
}

fn op() -> impl Strategy<Value = Op> {
    let scale = prop_oneof![0.2f32..3.0, -3.0f32..-0.2];
    prop_oneof![
        point().prop_map(Op::Translate),
        [scale.clone(), scale.clone(), scale].prop_map(Op::Scale),
        (0usize..3, -180.0f32..180.0).prop_map(|(axis, degrees)| Op::Rotate(axis, degrees)),
    ]
}

fn node() -> impl Strategy<Value = Node> {
    let leaf = prop_oneof![
        (point(), 0.1f32..1.5).prop_map(|(c, r)| Node::Sphere(c, r)),
        [point(), point(), point()].prop_map(Node::Triangle),
        (0usize..2).prop_map(Node::Mesh),
    ];
    leaf.prop_recursive(4, 40, 5, |inner| {
        prop_oneof![
            (prop::collection::vec(op(), 0..4), inner.clone())
                .prop_map(|(ops, child)| Node::Transform(ops, Box::new(child))),
            prop::collection::vec((0u32..3, inner), 1..5).prop_map(Node::Group),
        ]
    })
}

fn write_node(node: &Node, meshes: &[String; 2], out: &mut String) {
    let v = |p: &[f32; 3]| format!("{} {} {}", p[0], p[1], p[2]);
    match node {
        Node::Sphere(c, r) => writeln!(out, "Sphere {{ center {} radius {r} }}", v(c)).unwrap(),
        Node::Triangle(t) => writeln!(
            out,
            "Triangle {{ vertex0 {} vertex1 {} vertex2 {} }}",
            v(&t[0]),
            v(&t[1]),
            v(&t[2])
        )
        .unwrap(),
        Node::Mesh(i) => writeln!(out, "TriangleMesh {{ obj_file {} }}", meshes[*i]).unwrap(),
        Node::Plane => out.push_str("Plane { normal 0.3 1 0.1 offset -6 }\n"),
        Node::Transform(ops, child) => {
            out.push_str("Transform {\n");
            for op in ops {
                match op {
                    Op::Translate(t) => writeln!(out, "Translate {}", v(t)).unwrap(),
                    Op::Scale(s) => writeln!(out, "Scale {}", v(s)).unwrap(),
                    Op::Rotate(axis, d) => {
                        writeln!(out, "{}Rotate {d}", ["X", "Y", "Z"][*axis]).unwrap()
                    }
                }
            }
            write_node(child, meshes, out);
            out.push_str("}\n");
        }
        Node::Group(children) => {
            writeln!(out, "Group {{ numObjects {}", children.len()).unwrap();
            for (material, child) in children {
                writeln!(out, "MaterialIndex {material}").unwrap();
                write_node(child, meshes, out);
            }
            out.push_str("}\n");
        }
    }
}

/// A closed, bumpy mesh: a subdivided octahedron pushed out by a wobble, 128 triangles.
fn bumpy_mesh_obj(seed: u32) -> String {
    let mut vertices: Vec<Vec3A> = vec![
        Vec3A::X,
        -Vec3A::X,
        Vec3A::Y,
        -Vec3A::Y,
        Vec3A::Z,
        -Vec3A::Z,
    ];
    let mut faces: Vec<[usize; 3]> = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    for _ in 0..2 {
        let mut next = Vec::new();
        for [a, b, c] in faces {
            let mut mid = |i: usize, j: usize| {
                vertices.push(((vertices[i] + vertices[j]) * 0.5).normalize());
                vertices.len() - 1
            };
            let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
            next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        faces = next;
    }
    let mut text = String::from("# test mesh\n");
    for (i, v) in vertices.iter().enumerate() {
        let wobble = 1.0 + 0.3 * ((i as u32 * 7919 + seed * 104729) % 97) as f32 / 97.0;
        let p = *v * wobble;
        writeln!(text, "v {} {} {}", p.x, p.y, p.z).unwrap();
    }
    for [a, b, c] in faces {
        writeln!(text, "f {} {} {}", a + 1, b + 1, c + 1).unwrap();
    }
    text
}

fn ray() -> impl Strategy<Value = (bool, [f32; 3], [f32; 3])> {
    let direction = [-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0].prop_filter("a direction", |d| {
        d.iter().map(|x| x * x).sum::<f32>() > 1e-3
    });
    (
        any::<bool>(),
        [-8.0f32..8.0, -8.0f32..8.0, -8.0f32..8.0],
        direction,
    )
}

/// Rays for the grid: anywhere (many start inside the grid), along the axes and in the planes of
/// cell boundaries, and from far away.
fn grid_ray() -> impl Strategy<Value = (bool, [f32; 3], [f32; 3])> {
    let axis = (0usize..3, any::<bool>()).prop_map(|(a, positive)| {
        let mut d = [0.0f32; 3];
        d[a] = if positive { 1.0 } else { -1.0 };
        d
    });
    let grid_line = -4.0f32..4.0;
    prop_oneof![
        ray(),
        (
            any::<bool>(),
            [grid_line.clone(), grid_line.clone(), grid_line],
            axis.clone()
        )
            .prop_map(|(f, o, d)| (f, o, d)),
        // Through whole numbers, on the boundaries of cells of a unit grid over -4…4.
        (any::<bool>(), [-4i32..4, -4i32..4, -4i32..4], axis).prop_map(|(f, o, d)| (
            f,
            o.map(|v| v as f32),
            d
        )),
    ]
}

/// A ray's origin and direction.
type RaySpec = ([f32; 3], [f32; 3]);

/// A packet of 64 rays as the camera makes them, an 8×8 tile: from one point through a small
/// patch of directions (perspective), or along one direction from a small patch of points
/// (orthographic); `spread` sets the patch's size, and a wide one mixes the directions' signs.
fn packet() -> impl Strategy<Value = (bool, Vec<RaySpec>)> {
    let direction = [-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0].prop_filter("a direction", |d| {
        d.iter().map(|x| x * x).sum::<f32>() > 1e-2
    });
    let spread = prop_oneof![Just(0.0f32), 1e-4f32..1e-2, 1e-2f32..0.5];
    (
        any::<bool>(),
        [-8.0f32..8.0, -8.0f32..8.0, -8.0f32..8.0],
        direction,
        spread,
        any::<bool>(),
    )
        .prop_map(|(from_infinity, origin, direction, spread, perspective)| {
            let d = Vec3A::from(direction).normalize();
            let across = d.any_orthonormal_vector();
            let up = d.cross(across);
            let rays = (0..64)
                .map(|k| {
                    let (x, y) = ((k % 8) as f32 - 3.5, (k / 8) as f32 - 3.5);
                    let offset = (x * across + y * up) * spread;
                    let (o, d) = if perspective {
                        (Vec3A::from(origin), d + offset)
                    } else {
                        (Vec3A::from(origin) + offset, d)
                    };
                    (o.to_array(), d.to_array())
                })
                .collect();
            (from_infinity, rays)
        })
}

fn scene_text(root: &[(u32, Node)], with_plane: bool, meshes: &[String; 2]) -> String {
    let mut text = String::from(
        "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 5 }\n\
         Materials { numMaterials 3 Material { } Material { } Material { } }\n",
    );
    let mut objects = root.to_vec();
    if with_plane {
        objects.push((2, Node::Plane));
    }
    write_node(&Node::Group(objects), meshes, &mut text);
    text
}

/// The scene of `root` (and a floor, if `with_plane`), loaded, with its text for messages.
fn generated_scene(
    root: &[(u32, Node)],
    with_plane: bool,
) -> Result<(String, Scene), TestCaseError> {
    let dir = tempfile::tempdir().unwrap();
    let meshes = [0, 1].map(|i| {
        let path = dir.path().join(format!("m{i}.obj"));
        std::fs::write(&path, bumpy_mesh_obj(i)).unwrap();
        path.to_str().unwrap().to_string()
    });
    let text = scene_text(root, with_plane, &meshes);
    let description = parse_scene(Path::new("generated.txt"), &text)
        .map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
    let scene = Scene::from_description(&description).unwrap();
    Ok((text, scene))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn grid_closest_hit_and_occlusion_equal_brute_force(
        root in prop::collection::vec((0u32..3, node()), 1..8),
        rays in prop::collection::vec(grid_ray(), 64),
        with_plane in any::<bool>(),
        cells in [1u32..12, 1u32..12, 1u32..12],
    ) {
        let (text, mut scene) = generated_scene(&root, with_plane)?;
        scene.world.use_grid(glam::UVec3::from(cells)).unwrap();
        for (from_infinity, origin, direction) in rays {
            let ray = Ray::new(Vec3A::from(origin), Vec3A::from(direction).normalize());
            let t_min = if from_infinity { f32::NEG_INFINITY } else { 0.0 };
            let fast = scene.world.intersect(&ray, t_min);
            let slow = scene.world.intersect_brute_force(&ray, t_min);
            prop_assert_eq!(fast, slow, "ray {:?}, grid {:?}, in scene\n{}", ray, cells, text);
            for t_max in [0.5f32, 3.0, f32::INFINITY] {
                prop_assert_eq!(
                    scene.world.occluded(&ray, t_min.max(0.0), t_max),
                    scene.world.occluded_brute_force(&ray, t_min.max(0.0), t_max),
                    "shadow ray {:?} to {}, grid {:?}, in scene\n{}", ray, t_max, cells, text
                );
            }
        }
    }

    #[test]
    fn bvh_closest_hit_equals_brute_force(
        root in prop::collection::vec((0u32..3, node()), 1..8),
        rays in prop::collection::vec(ray(), 64),
        with_plane in any::<bool>(),
    ) {
        let (text, scene) = generated_scene(&root, with_plane)?;
        for (from_infinity, origin, direction) in rays {
            let ray = Ray::new(Vec3A::from(origin), Vec3A::from(direction).normalize());
            let t_min = if from_infinity { f32::NEG_INFINITY } else { 0.0 };
            let fast = scene.world.intersect(&ray, t_min);
            let slow = scene.world.intersect_brute_force(&ray, t_min);
            prop_assert_eq!(fast, slow, "ray {:?} in scene\n{}", ray, text);
        }
    }

    #[test]
    fn bvh_any_hit_equals_brute_force(
        root in prop::collection::vec((0u32..3, node()), 1..8),
        rays in prop::collection::vec(ray(), 64),
        with_plane in any::<bool>(),
    ) {
        let (text, scene) = generated_scene(&root, with_plane)?;
        for (_, origin, direction) in rays {
            let ray = Ray::new(Vec3A::from(origin), Vec3A::from(direction).normalize());
            let nearest = scene.world.intersect_brute_force(&ray, 0.0).map(|hit| hit.t);
            // Ranges that end just before, at and just after the nearest hit (where an any-hit
            // search that stops at the first box it enters, or a limit off by one ulp, differs),
            // ranges that start at it, and the usual ones.
            let mut ranges = vec![(0.0, 0.5), (0.0, 3.0), (0.0, f32::INFINITY), (1e-4, f32::MAX)];
            if let Some(t) = nearest {
                let below = f32::from_bits(t.to_bits().saturating_sub(1));
                let above = f32::from_bits(t.to_bits() + 1);
                ranges.extend([(0.0, below), (0.0, t), (0.0, above), (t, f32::INFINITY), (above, 10.0 * t + 1.0)]);
            }
            for (t_min, t_max) in ranges {
                let fast = scene.world.occluded(&ray, t_min, t_max);
                let slow = scene.world.occluded_brute_force(&ray, t_min, t_max);
                prop_assert_eq!(
                    fast, slow,
                    "shadow ray {:?} over [{}, {}] in scene\n{}", ray, t_min, t_max, text
                );
            }
            // Over the whole ray, something is hit exactly when there is a nearest hit.
            prop_assert_eq!(scene.world.occluded(&ray, 0.0, f32::INFINITY), nearest.is_some());
        }
    }

    #[test]
    fn a_packet_finds_what_each_of_its_rays_finds_alone(
        root in prop::collection::vec((0u32..3, node()), 1..8),
        packets in prop::collection::vec(packet(), 8),
        with_plane in any::<bool>(),
    ) {
        let (text, scene) = generated_scene(&root, with_plane)?;
        for (from_infinity, rays) in packets {
            let rays: Vec<Ray> = rays
                .iter()
                .map(|&(o, d)| Ray::new(Vec3A::from(o), Vec3A::from(d)))
                .collect();
            let t_min = if from_infinity { f32::NEG_INFINITY } else { 0.0 };
            // Whole packets, and the short ones at a picture's edge.
            for len in [64, 24, 3] {
                let mut together = vec![None; len];
                scene.world.intersect_packet_with(&rays[..len], t_min, &mut together, &mut ());
                for (ray, together) in rays.iter().zip(&together) {
                    let alone = scene.world.intersect(ray, t_min);
                    prop_assert_eq!(*together, alone, "ray {:?} in scene\n{}", ray, text);
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    /// Shadow rays cast together answer as each alone: the packets of the strategy above, each
    /// ray over a range of its own, and the shadow rays that the points a packet hits send
    /// toward a directional light and toward a point light (the tracer's use).
    #[test]
    fn a_packet_of_shadow_rays_is_answered_as_each_ray_alone(
        root in prop::collection::vec((0u32..3, node()), 1..8),
        packets in prop::collection::vec(packet(), 4),
        with_plane in any::<bool>(),
        light in [-6.0f32..6.0, -6.0f32..6.0, -6.0f32..6.0],
    ) {
        let (text, scene) = generated_scene(&root, with_plane)?;
        let light = Vec3A::from(light);
        for (_, rays) in packets {
            let rays: Vec<Ray> = rays
                .iter()
                .map(|&(o, d)| Ray::new(Vec3A::from(o), Vec3A::from(d)))
                .collect();
            let hits: Vec<Vec3A> = rays
                .iter()
                .filter_map(|ray| Some(ray.at(scene.world.intersect(ray, 0.0)?.t)))
                .collect();
            let toward_sun: Vec<Ray> = hits.iter().map(|&p| Ray::new(p, light)).collect();
            let toward_lamp: Vec<Ray> = hits.iter().map(|&p| Ray::new(p, light - p)).collect();
            for rays in [&rays, &toward_sun, &toward_lamp] {
                let n = rays.len();
                let t_min: Vec<f32> = (0..n).map(|k| [0.0, 1e-4, 1e-2, 0.3][k % 4]).collect();
                let t_max: Vec<f32> = (0..n)
                    .map(|k| [f32::INFINITY, 1.0 - 1e-3, 0.5, f32::MAX, 4.0][k % 5])
                    .collect();
                let mut together = vec![false; n];
                scene.world.occluded_packet_with(rays, &t_min, &t_max, &mut together, &mut ());
                for (k, ray) in rays.iter().enumerate() {
                    let alone = scene.world.occluded(ray, t_min[k], t_max[k]);
                    prop_assert_eq!(
                        together[k], alone,
                        "shadow ray {:?} over [{}, {}] in scene\n{}", ray, t_min[k], t_max[k], text
                    );
                }
            }
        }
    }
}

/// Every scene of the course, seen through its own camera at 64×64: each 8×8 packet of rays
/// searched as a packet find what each finds alone (the pictures' pixels, before shading).
#[test]
fn every_course_scene_finds_the_same_hits_by_packet() {
    let dirs = [
        common::data_dir(
            "a1-a2 scenes",
            "RAYCAST_CONFORMANCE_DIR",
            "../shared/conformance",
            "COMMANDS.txt",
        ),
        common::later_dir("a3-a7 scenes"),
    ];
    let mut scenes = 0;
    for dir in dirs.into_iter().flatten() {
        let mut paths: Vec<_> = std::fs::read_dir(dir.join("scenes"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "txt"))
            .collect();
        paths.sort();
        for path in paths {
            let Ok(scene) = Scene::load(&path) else {
                continue;
            };
            scenes += 1;
            let t_min = scene.camera.t_min();
            let size = 64;
            for (top, left) in
                (0..size / 8).flat_map(|r| (0..size / 8).map(move |c| (r * 8, c * 8)))
            {
                let rays: Vec<Ray> = (0..64)
                    .map(|k| {
                        let (u, v) =
                            raycast::camera::pixel_to_screen(left + k % 8, top + k / 8, size, size);
                        scene.camera.ray(u, v)
                    })
                    .collect();
                let mut together = vec![None; 64];
                scene
                    .world
                    .intersect_packet_with(&rays, t_min, &mut together, &mut ());
                for (ray, together) in rays.iter().zip(&together) {
                    assert_eq!(
                        *together,
                        scene.world.intersect(ray, t_min),
                        "{}",
                        path.display()
                    );
                }
            }
        }
    }
    let line = format!("course scenes by packet: {scenes} scenes, same hits\n");
    let _ = std::io::Write::write_all(&mut std::io::stderr(), line.as_bytes());
}

/// A packet whose bounds take in a sphere's box while each of its rays passes beside it: under
/// the orthographic camera (whose rays start at t = -∞) no ray may test the sphere.
#[test]
fn a_packet_ray_that_misses_a_box_tests_nothing_in_it() {
    let text = "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 5 }\n\
                Materials { numMaterials 1 Material { } }\n\
                Group { numObjects 2 MaterialIndex 0\n\
                Sphere { center 0 0 0 radius 0.5 }\n\
                Sphere { center 0 10 0 radius 0.5 } }\n";
    let description = parse_scene(Path::new("beside.txt"), text).unwrap();
    let scene = Scene::from_description(&description).unwrap();
    let rays: Vec<Ray> = (0..16)
        .map(|k| {
            let x = if k % 2 == 0 { -2.0 } else { 2.0 };
            Ray::new(Vec3A::new(x, (k / 2) as f32 * 0.01, 10.0), -Vec3A::Z)
        })
        .collect();
    let t_min = scene.camera.t_min();
    assert_eq!(t_min, f32::NEG_INFINITY);
    let mut hits = vec![None; rays.len()];
    let mut tallies = raycast::accel::Tallies::default();
    scene
        .world
        .intersect_packet_with(&rays, t_min, &mut hits, &mut tallies);
    assert_eq!(hits, vec![None; rays.len()]);
    assert_eq!(tallies.intersections, 0);
}
