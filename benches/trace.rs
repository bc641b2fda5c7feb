//! Speed of the two things that decide a big render: building the BVH and tracing primary rays.
//!
//! `cargo bench` (needs ../shared/meshes and ../shared/bench beside the project). Meshes: the
//! Stanford bunny (69,451 triangles), Nefertiti (~100k) and a generated sphere of about a million
//! triangles. Traversal renders a fixed 1024x1024 view (the colour picture, primary rays only);
//! divan reports it as items per second, one item being one primary ray.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use divan::Bencher;
use divan::counter::ItemsCount;
use glam::Vec3;
use raycast::accel::TriangleMesh;
use raycast::parse::obj::parse_obj;
use raycast::render::{RenderSettings, render};
use raycast::{Scene, parse::parse_scene};

fn main() {
    divan::main();
}

const MESHES: &[&str] = &["bunny", "nefertiti", "sphere_1m"];
const SIZE: u32 = 1024;

fn shared() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared")
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
}

fn all_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// A UV sphere of `rings` × `segments` × 2 triangles (rings 707, segments 707: ~1M).
fn sphere_obj(rings: usize, segments: usize) -> String {
    let mut text = String::with_capacity(rings * segments * 60);
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..segments {
            let phi = std::f32::consts::TAU * s as f32 / segments as f32;
            let bump = 1.0 + 0.02 * (7.0 * phi).sin() * (5.0 * theta).sin();
            let (x, y, z) = (
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            text += &format!("v {} {} {}\n", x * bump, y * bump, z * bump);
        }
    }
    for r in 0..rings {
        for s in 0..segments {
            let a = r * segments + s + 1;
            let b = r * segments + (s + 1) % segments + 1;
            let (c, d) = (a + segments, b + segments);
            text += &format!("f {a} {c} {d}\nf {a} {d} {b}\n");
        }
    }
    text
}

/// The generated mesh, written once into the target folder so scenes can name it.
fn sphere_path() -> &'static Path {
    static PATH: OnceLock<PathBuf> = OnceLock::new();
    PATH.get_or_init(|| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/bench-sphere-1m.obj");
        if !path.is_file() {
            std::fs::write(&path, sphere_obj(707, 707)).unwrap();
        }
        path
    })
}

fn mesh_path(name: &str) -> PathBuf {
    match name {
        "bunny" => shared().join("meshes/stanford-bunny.obj"),
        "nefertiti" => shared().join("meshes/nefertiti.obj"),
        _ => sphere_path().to_path_buf(),
    }
}

fn triangles(name: &str) -> Vec<[Vec3; 3]> {
    let path = mesh_path(name);
    let obj = parse_obj(&path, &std::fs::read(&path).unwrap()).unwrap();
    obj.triangles
        .iter()
        .map(|t| t.map(|i| obj.positions[i as usize]))
        .collect()
}

/// The bench scenes' views of the bunny and Nefertiti; the sphere seen whole.
fn scene(name: &str) -> Scene {
    let path = match name {
        "bunny" => shared().join("bench/scenes/bunny.txt"),
        "nefertiti" => shared().join("bench/scenes/nefertiti.txt"),
        _ => {
            let text = format!(
                "PerspectiveCamera {{ center 0 0 4 direction 0 0 -1 up 0 1 0 angle 35 }}\n\
                 Lights {{ numLights 1 DirectionalLight {{ direction 0.3 -0.8 -0.6 color 0.9 0.9 0.9 }} }}\n\
                 Background {{ color 0.2 0.2 0.2 ambientLight 0.1 0.1 0.1 }}\n\
                 Materials {{ numMaterials 1 Material {{ diffuseColor 0.9 0.9 0.9 }} }}\n\
                 Group {{ numObjects 1 MaterialIndex 0 TriangleMesh {{ obj_file {} }} }}\n",
                sphere_path().display()
            );
            let description = parse_scene(Path::new("sphere_1m.txt"), &text).unwrap();
            return Scene::from_description(&description).unwrap();
        }
    };
    Scene::load(&path).unwrap()
}

#[divan::bench(args = MESHES, sample_count = 10, sample_size = 1)]
fn build_one_thread(bencher: Bencher, name: &str) {
    let input = triangles(name);
    let pool = pool(1);
    bencher
        .counter(ItemsCount::new(input.len()))
        .with_inputs(|| input.clone())
        .bench_local_values(|t| pool.install(|| TriangleMesh::new(t)));
}

#[divan::bench(args = MESHES, sample_count = 10, sample_size = 1)]
fn build_all_threads(bencher: Bencher, name: &str) {
    let input = triangles(name);
    let pool = pool(all_threads());
    bencher
        .counter(ItemsCount::new(input.len()))
        .with_inputs(|| input.clone())
        .bench_local_values(|t| pool.install(|| TriangleMesh::new(t)));
}

fn trace(bencher: Bencher, name: &str, threads: usize) {
    let scene = scene(name);
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        colour: true,
        normals: false,
        depth: None,
        trace: raycast::trace::TraceSettings::default(),
        progress: false,
        counter: None,
        stop: None,
        sampling: Default::default(),
        keep_film: false,
    };
    let pool = pool(threads);
    bencher
        .counter(ItemsCount::new((SIZE * SIZE) as usize))
        .bench_local(|| pool.install(|| render(&scene, &settings)));
}

#[divan::bench(args = MESHES, sample_count = 10, sample_size = 1)]
fn trace_one_thread(bencher: Bencher, name: &str) {
    trace(bencher, name, 1);
}

#[divan::bench(args = MESHES, sample_count = 10, sample_size = 1)]
fn trace_all_threads(bencher: Bencher, name: &str) {
    trace(bencher, name, all_threads());
}
