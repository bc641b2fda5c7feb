//! Mutation testing: valid scene and mesh files, broken in every way a hand, an editor or a
//! disk can break them, must give either a render or an error that names `file:line:column`
//! inside the file. Never a panic, never an error without a place.
//!
//! The valid inputs are every course scene and mesh (from RAYCAST_CONFORMANCE_DIR, or
//! ../shared/conformance beside the project), plus scenes and a real-world OBJ written here, so
//! that the test means something without the course data too. Each case takes one input and
//! applies one to three mutations: a token deleted, duplicated or swapped with another; a number
//! replaced by a huge, tiny, negative, non-finite or malformed one; a token replaced by a keyword
//! of the format; the file cut at any byte; bytes inserted (NUL and invalid UTF-8 among them); a
//! byte's bits flipped. Scenes are parsed from text, or, when they name a mesh or are not UTF-8,
//! written into a temporary folder beside the meshes and loaded from there. OBJ text goes to
//! `parse_obj`, and a mesh that reads is also loaded by a scene and rendered. Every mutant that
//! loads is rendered at 4×4 (colour, normals and depth), and every hit of its rays must have a
//! finite t and normal.
//!
//! RAYCAST_MUTATION_CASES sets the number of cases (default 100,000; about 10 s in release on a
//! 2-core machine). The random generator has a fixed seed (RAYCAST_MUTATION_SEED overrides it)
//! and proptest's failure persistence is off, so every run tries the same cases and writes no
//! files into the project. A failure is shrunk to the fewest, smallest mutations and reported
//! with the mutated text.

use std::cell::Cell;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestCaseError, TestError, TestRunner};

use raycast::parse::obj::parse_obj;
use raycast::parse::parse_scene;
use raycast::{Error, RenderSettings, Scene};

const DEFAULT_CASES: u32 = 100_000;
const DEFAULT_SEED: u64 = 6837;

// ---------------------------------------------------------------------------------------------
// The valid inputs

/// Every feature of the format in one scene, with a mesh written by a modelling tool.
const FULL_SCENE: &str = "\
PerspectiveCamera {
    center 1 2 12
    direction -0.1 -0.15 -1
    up 0 1 0
    angle 40
}
Background { color 0.1 0.2 0.3 ambientLight 0.2 0.2 0.2 }
Lights {
    numLights 3
    DirectionalLight { direction -1 -1 -1 color 0.8 0.7 0.6 }
    DirectionalLight { direction 0.5 -0.2 -1 color 0.2 0.3 0.4 }
    PointLight { position 0 4 3 color 0.9 0.9 0.9 attenuation 0.5 0.1 0.02 }
}
Materials {
    numMaterials 3
    Material { diffuseColor 1 0 0 specularColor 0.5 0.5 0.5 exponent 20 reflectiveColor 0.3 0.3 0.3 }
    PhongMaterial { diffuseColor 0 1 0 transparentColor 0.6 0.6 0.6 indexOfRefraction 1.4 }
    Material { }
}
Group {
    numObjects 6
    MaterialIndex 0
    Sphere { center 0 0 0 radius 1 }
    MaterialIndex 1
    Plane { normal 0 1 0 offset -2 }
    Triangle { vertex0 -3 -1 0 vertex1 -1 -1 0 vertex2 -2 1 0 }
    Transform {
        Translate 2 0 0
        Scale 1 0.5 2
        UniformScale 0.8
        XRotate 10 YRotate -20 ZRotate 30
        Rotate { 1 1 0 45 }
        Matrix { 1 0.2 0 0  0 1 0 0  0 0 1 0  0 0 0 1 }
        TriangleMesh { obj_file real.obj }
    }
    Group {
        numObjects 2
        MaterialIndex 2
        Transform { Translate 0 3 0 Sphere { center 0 0 0 radius 0.5 } }
        Transform { Scale -1 1 1 Triangle { vertex0 1 2 0 vertex1 2 2 0 vertex2 1 3 0 } }
    }
    Transform { Translate -2 2 -1 Transform { YRotate 45 TriangleMesh { obj_file real.obj } } }
}
";

/// Assignment 1's form: orthographic, no lights, PhongMaterial.
const FLAT_SCENE: &str = "\
OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 5 }
Background { color 0 0 0 }
Materials { numMaterials 2 PhongMaterial { diffuseColor 1 0 0 } PhongMaterial { diffuseColor 0 0 1 } }
Group { numObjects 3
  MaterialIndex 0 Sphere { center 0 0 0 radius 1 }
  MaterialIndex 1 Sphere { center 1 1 -1 radius 0.75 }
  Sphere { center -1 -1 1 radius 0.5 }
}
";

/// A mesh placed twice, inside nested groups, with a camera that looks up at it.
const MESH_SCENE: &str = "\
PerspectiveCamera { center 0 -3 8 direction 0 0.3 -1 up 0 1 0 angle 50 }
Lights { numLights 1 DirectionalLight { direction 0 0 -1 color 1 1 1 } }
Materials { numMaterials 1 Material { diffuseColor 0.9 0.8 0.7 } }
Group { numObjects 2 MaterialIndex 0
  Group { numObjects 1 Transform { Translate -1.5 0 0 TriangleMesh { obj_file real.obj } } }
  Transform { Translate 1.5 0 0 XRotate 90 TriangleMesh { obj_file real.obj } }
}
";

/// An OBJ as tools write them: comments, normals and texture coordinates, `a/b/c` and `a//c`
/// references, quads, negative indices, groups and materials, Windows line ends.
const REAL_OBJ: &str = "\
# Exported by a modelling tool\r
mtllib pyramid.mtl\r
o pyramid\r
v -1 0 -1\r
v 1 0 -1\r
v 1 0 1\r
v -1 0 1\r
v 0 1.5 0 1.0\r
vn 0 -1 0\r
vn 0 0.55 0.83\r
vt 0 0\r
vt 1 0\r
vt 0.5 1\r
g base\r
usemtl stone\r
s off\r
f 1/1/1 2/2/1 3/3/1 4/1/1\r
g sides\r
s 1\r
f 4//2 3//2 5//2 # front\r
f -4 -1 -3\r
f 2/2 5/3 3/1\r
f 1 4 5\r
";

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Scene,
    Obj,
}

struct Input {
    name: String,
    kind: Kind,
    bytes: Vec<u8>,
}

/// A folder of the course's scenes, or None (with a warning) where it is not to be found.
fn course_folder(variable: &str, default: &str) -> Option<PathBuf> {
    let root = match std::env::var_os(variable) {
        Some(dir) => PathBuf::from(dir),
        None => Path::new(env!("CARGO_MANIFEST_DIR")).join(default),
    };
    let scenes = root.join("scenes");
    if scenes.is_dir() {
        Some(scenes)
    } else {
        // Past the test harness's capture, so that `cargo test` shows it.
        let _ = writeln!(
            std::io::stderr(),
            "skipped: mutating the course's scenes (no course data at {}; put it there or set \
             {variable} to mutate them too)",
            scenes.display()
        );
        None
    }
}

/// The files of the course to mutate: every scene and mesh of assignments 1 and 2, the scenes
/// of assignments 3 to 7 (Phong materials, point lights, mirrors, glass, solid textures) and
/// their small meshes (scenes that name the big ones are refused at the mesh, still with a
/// place).
fn course_files() -> Vec<(PathBuf, bool)> {
    let mut files = Vec::new();
    if let Some(scenes) = course_folder("RAYCAST_CONFORMANCE_DIR", "../shared/conformance") {
        files.extend(
            std::fs::read_dir(&scenes)
                .unwrap()
                .map(|e| (e.unwrap().path(), true)),
        );
    }
    if let Some(scenes) = course_folder("RAYCAST_LATER_DIR", "../shared/later-assignments") {
        let scene = |name: &str| {
            ["scene3_", "scene4_", "scene5_", "scene6_", "scene7_"]
                .iter()
                .any(|prefix| name.starts_with(prefix))
        };
        let small_mesh = |name: &str| {
            ["cube.obj", "bunny_200.obj", "bunny_1k.obj", "diamond.obj"].contains(&name)
        };
        for entry in std::fs::read_dir(&scenes).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            // Big meshes are there for the scenes to load, not to be mutated themselves.
            if scene(&name) || name.ends_with(".obj") {
                files.push((path, scene(&name) || small_mesh(&name)));
            }
        }
    }
    files.sort();
    files
}

/// The inputs, and a folder holding every mesh they name (where mutated scenes are loaded).
fn inputs() -> (Vec<Input>, tempfile::TempDir) {
    let folder = tempfile::tempdir().unwrap();
    std::fs::write(folder.path().join("real.obj"), REAL_OBJ).unwrap();
    let mut inputs: Vec<Input> = [
        ("full.txt", Kind::Scene, FULL_SCENE),
        ("flat.txt", Kind::Scene, FLAT_SCENE),
        ("mesh.txt", Kind::Scene, MESH_SCENE),
        ("real.obj", Kind::Obj, REAL_OBJ),
    ]
    .into_iter()
    .map(|(name, kind, text)| Input {
        name: name.into(),
        kind,
        bytes: text.as_bytes().to_vec(),
    })
    .collect();
    for (path, mutate) in course_files() {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let kind = match path.extension().and_then(|e| e.to_str()) {
            Some("txt") => Kind::Scene,
            Some("obj") => Kind::Obj,
            _ => continue,
        };
        let bytes = std::fs::read(&path).unwrap();
        if kind == Kind::Obj {
            std::fs::write(folder.path().join(&name), &bytes).unwrap();
        }
        if mutate {
            inputs.push(Input { name, kind, bytes });
        }
    }
    (inputs, folder)
}

// ---------------------------------------------------------------------------------------------
// Mutations

/// Replacements for a number: beyond single precision, beyond raycast's bound, at it, below
/// single precision's smallest, signs, non-finite values, malformed numbers, counts.
#[rustfmt::skip]
const NUMBERS: &[&str] = &[
    "1e39", "3e38", "-3e38", "1e20", "1e15", "1e10", "1.5e9", "1e9", "-1e9", "1e8", "-1e5",
    "1e-45", "-1e-45", "1e-30", "1e-300", "1e-9", "0", "-0", "-1", "-5", "0.5", ".25", "1.", "+7",
    "2", "3", "10", "100", "NaN", "nan", "inf", "-inf", "infinity", "1e", "--1", "0x10", "1,5",
    ".", "-", "five", "4294967295", "4294967296", "99999",
];

/// Every word of the scene format (later assignments' too) and of OBJ files, and mesh names.
#[rustfmt::skip]
const KEYWORDS: &[&str] = &[
    "OrthographicCamera", "PerspectiveCamera", "center", "direction", "up", "size", "angle",
    "Background", "color", "ambientLight", "Lights", "numLights", "DirectionalLight", "Materials",
    "numMaterials", "Material", "PhongMaterial", "diffuseColor", "Group", "numObjects",
    "MaterialIndex", "Sphere", "radius", "Plane", "normal", "offset", "Triangle", "vertex0",
    "vertex1", "vertex2", "TriangleMesh", "obj_file", "Transform", "Scale", "UniformScale",
    "Translate", "XRotate", "YRotate", "ZRotate", "Rotate", "Matrix", "{", "}", "specularColor",
    "exponent", "PointLight", "position", "attenuation", "reflectiveColor", "transparentColor",
    "indexOfRefraction", "Checkerboard", "Noise", "Marble", "Wood", "materialIndex", "octaves",
    "frequency", "amplitude", "v", "f", "vn", "vt", "g", "o", "s", "usemtl",
    "mtllib", "#", "1/2/3", "1//1", "-1", "cube.obj", "bunny_200.obj", "real.obj", "missing.obj",
];

#[derive(Clone, Debug)]
enum Mutation {
    Delete(usize),
    Duplicate(usize),
    Swap(usize, usize),
    /// A number token (or any token, where there is none) becomes `NUMBERS[k]`, or is negated.
    Number(usize, usize),
    Keyword(usize, usize),
    Truncate(usize),
    Insert(usize, Vec<u8>),
    /// The byte at a position is XORed with a non-zero mask.
    Flip(usize, u8),
    /// Whitespace before a token: the file means the same, but every place after it moves.
    Space(usize, &'static str),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let byte = prop_oneof![
        Just(0u8),
        Just(0xff),
        Just(0xc3),
        Just(0x80),
        Just(b'{'),
        Just(b'}'),
        Just(b'\n'),
        Just(b' '),
        Just(b'#'),
        Just(b'/'),
        Just(b'-'),
        Just(b'e'),
        any::<u8>(),
    ];
    // Numbers and keywords weigh more: most of a scene's checks are about what stands where.
    prop_oneof![
        1 => any::<usize>().prop_map(Mutation::Delete),
        1 => any::<usize>().prop_map(Mutation::Duplicate),
        1 => (any::<usize>(), any::<usize>()).prop_map(|(i, j)| Mutation::Swap(i, j)),
        3 => (any::<usize>(), 0..=NUMBERS.len()).prop_map(|(i, k)| Mutation::Number(i, k)),
        2 => (any::<usize>(), 0..KEYWORDS.len()).prop_map(|(i, k)| Mutation::Keyword(i, k)),
        1 => any::<usize>().prop_map(Mutation::Truncate),
        1 => (any::<usize>(), prop::collection::vec(byte, 1..4))
            .prop_map(|(i, b)| Mutation::Insert(i, b)),
        1 => (any::<usize>(), prop_oneof![(0..8u32).prop_map(|bit| 1u8 << bit), 1..=255u8])
            .prop_map(|(i, mask)| Mutation::Flip(i, mask)),
        1 => (any::<usize>(), prop::sample::select(&[" ", "\t", "\n", "\r\n", "\x0c", "\n\n  "][..]))
            .prop_map(|(i, space)| Mutation::Space(i, space)),
    ]
}

/// Byte ranges of the words, split as the lexer and the OBJ reader split them.
fn tokens(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut tokens = Vec::new();
    let mut start = None;
    for (i, b) in bytes.iter().enumerate() {
        match (b.is_ascii_whitespace(), start) {
            (false, None) => start = Some(i),
            (true, Some(s)) => {
                tokens.push((s, i));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        tokens.push((s, bytes.len()));
    }
    tokens
}

fn replace(bytes: &mut Vec<u8>, (start, end): (usize, usize), with: &[u8]) {
    bytes.splice(start..end, with.iter().copied());
}

fn apply(bytes: &mut Vec<u8>, mutation: &Mutation) {
    let words = tokens(bytes);
    let pick = |i: usize| words[i % words.len()];
    match *mutation {
        Mutation::Truncate(at) => bytes.truncate(at % (bytes.len() + 1)),
        Mutation::Insert(at, ref new) => {
            let at = at % (bytes.len() + 1);
            bytes.splice(at..at, new.iter().copied());
        }
        Mutation::Flip(at, mask) => {
            if !bytes.is_empty() {
                let at = at % bytes.len();
                bytes[at] ^= mask;
            }
        }
        _ if words.is_empty() => {}
        Mutation::Delete(i) => replace(bytes, pick(i), b""),
        Mutation::Duplicate(i) => {
            let (start, end) = pick(i);
            let mut copy = bytes[start..end].to_vec();
            copy.push(b' ');
            bytes.splice(start..start, copy);
        }
        Mutation::Swap(i, j) => {
            let (a, b) = (pick(i), pick(j));
            let (first, second) = if a.0 <= b.0 { (a, b) } else { (b, a) };
            if first != second {
                let (x, y) = (
                    bytes[first.0..first.1].to_vec(),
                    bytes[second.0..second.1].to_vec(),
                );
                // The later one first, so that the earlier range still holds.
                replace(bytes, second, &x);
                replace(bytes, first, &y);
            }
        }
        Mutation::Number(i, k) => {
            let numbers: Vec<(usize, usize)> = words
                .iter()
                .copied()
                .filter(|&(s, e)| {
                    std::str::from_utf8(&bytes[s..e]).is_ok_and(|t| t.parse::<f64>().is_ok())
                })
                .collect();
            let range = match numbers.len() {
                0 => pick(i),
                n => numbers[i % n],
            };
            let new = match NUMBERS.get(k) {
                Some(number) => number.as_bytes().to_vec(),
                None => match bytes[range.0..range.1].strip_prefix(b"-") {
                    Some(positive) => positive.to_vec(),
                    None => [b"-", &bytes[range.0..range.1]].concat(),
                },
            };
            replace(bytes, range, &new);
        }
        Mutation::Keyword(i, k) => replace(bytes, pick(i), KEYWORDS[k].as_bytes()),
        Mutation::Space(i, space) => {
            let start = pick(i).0;
            bytes.splice(start..start, space.bytes());
        }
    }
}

// ---------------------------------------------------------------------------------------------
// What each mutant must do

/// An error must be a [`raycast::Diagnostic`] whose line and column lie inside the file it names
/// (or just past its end). `mutant` is where the mutated `bytes` are (or would be) written; any
/// other file named is read from the disk.
fn check_error(error: &Error, mutant: &Path, bytes: &[u8]) -> Result<(), TestCaseError> {
    let Error::Input(diagnostic) = error else {
        return Err(TestCaseError::fail(format!(
            "an error without file:line:column: {error}"
        )));
    };
    let named: Vec<u8>;
    let text = if diagnostic.path == mutant {
        bytes
    } else {
        // A mesh the scene names, beside it or in the working directory.
        named = std::fs::read(&diagnostic.path).map_err(|e| {
            TestCaseError::fail(format!("{error}: the file it names cannot be read: {e}"))
        })?;
        &named
    };
    let (line, column) = (
        diagnostic.span.line as usize,
        diagnostic.span.column as usize,
    );
    let lines: Vec<&[u8]> = text.split(|&b| b == b'\n').collect();
    prop_assert!(
        (1..=lines.len()).contains(&line),
        "{error}: line {line} is outside the file's {} lines",
        lines.len()
    );
    let characters = lines[line - 1]
        .iter()
        .filter(|&&b| b & 0xC0 != 0x80)
        .count();
    prop_assert!(
        (1..=characters + 1).contains(&column),
        "{error}: column {column} is outside line {line}, of {characters} characters"
    );
    let place = format!("{}:{line}:{column}: ", diagnostic.path.display());
    prop_assert!(error.to_string().starts_with(&place), "{error}");
    Ok(())
}

/// Renders all three pictures at 4×4, and checks every hit of their rays for NaN.
fn render(scene: &Scene, shade_back: bool) -> Result<(), TestCaseError> {
    const SIZE: u32 = 4;
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        colour: true,
        normals: true,
        depth: Some((-5.0, 20.0)),
        // The whole tracer: shadow rays, mirrors and glass meet the damaged scenes too.
        trace: raycast::trace::TraceSettings {
            shade_back,
            shadows: true,
            bounces: 3,
            ..Default::default()
        },
        progress: false,
        counter: None,
        stop: None,
        sampling: Default::default(),
        keep_film: false,
    };
    let rendered = raycast::render::render(scene, &settings);
    prop_assert_eq!(rendered.colour.unwrap().pixels.len(), 16);
    for j in 0..SIZE {
        for i in 0..SIZE {
            let (u, v) = raycast::camera::pixel_to_screen(i, j, SIZE, SIZE);
            let ray = scene.camera.ray(u, v);
            if let Some(hit) = scene.world.intersect(&ray, scene.camera.t_min()) {
                prop_assert!(
                    hit.t.is_finite() && hit.normal.is_finite(),
                    "pixel ({}, {}): t {} normal {}",
                    i,
                    j,
                    hit.t,
                    hit.normal
                );
            }
        }
    }
    Ok(())
}

#[derive(Default)]
struct Counts {
    refused: Cell<u32>,
    rendered: Cell<u32>,
}

impl Counts {
    fn add(&self, loaded: bool) {
        let counter = if loaded {
            &self.rendered
        } else {
            &self.refused
        };
        counter.set(counter.get() + 1);
    }
}

fn check_scene(
    folder: &Path,
    bytes: &[u8],
    shade_back: bool,
    counts: &Counts,
) -> Result<(), TestCaseError> {
    let path = folder.join("mutant.txt");
    let text = std::str::from_utf8(bytes).ok();
    // Parsed from memory where nothing needs the disk: most cases, and the fastest.
    let loaded = match text {
        Some(text) if !text.contains("obj_file") => parse_scene(&path, text)
            .map_err(Error::from)
            .and_then(|description| Scene::from_description(&description)),
        _ => {
            std::fs::write(&path, bytes).unwrap();
            Scene::load(&path)
        }
    };
    counts.add(loaded.is_ok());
    match loaded {
        Ok(scene) => render(&scene, shade_back),
        Err(error) => check_error(&error, &path, bytes),
    }
}

fn check_obj(
    folder: &Path,
    bytes: &[u8],
    shade_back: bool,
    counts: &Counts,
) -> Result<(), TestCaseError> {
    let path = folder.join("mutant.obj");
    match parse_obj(&path, bytes) {
        Err(diagnostic) => {
            counts.add(false);
            check_error(&Error::Input(diagnostic), &path, bytes)
        }
        Ok(_) => {
            // Read fine: placed in a scene, it must load and render, or be refused with a place
            // (a mesh carried beyond the bound by its Transform, say).
            std::fs::write(&path, bytes).unwrap();
            let scene = folder.join("host.txt");
            std::fs::write(
                &scene,
                "PerspectiveCamera { center 0 0 5 direction 0 0 -1 up 0 1 0 angle 60 }\n\
                 Materials { numMaterials 1 Material { diffuseColor 1 1 1 } }\n\
                 Group { numObjects 2 MaterialIndex 0\n\
                 TriangleMesh { obj_file mutant.obj }\n\
                 Transform { Translate 0 1 -1 UniformScale 0.5 TriangleMesh { obj_file mutant.obj } } }\n",
            )
            .unwrap();
            match Scene::load(&scene) {
                Ok(scene) => {
                    counts.add(true);
                    render(&scene, shade_back)
                }
                Err(error) => {
                    counts.add(false);
                    check_error(&error, &path, bytes)
                }
            }
        }
    }
}

fn env_number<T: std::str::FromStr>(name: &str, default: T) -> T {
    match std::env::var(name) {
        Ok(value) => value
            .parse()
            .unwrap_or_else(|_| panic!("{name} should be a whole number, not '{value}'")),
        Err(_) => default,
    }
}

#[test]
fn mutated_inputs_render_or_are_refused_with_a_place() {
    let (inputs, folder) = inputs();
    let cases = env_number("RAYCAST_MUTATION_CASES", DEFAULT_CASES);
    let seed = env_number("RAYCAST_MUTATION_SEED", DEFAULT_SEED);
    let config = Config {
        cases,
        rng_seed: RngSeed::Fixed(seed),
        failure_persistence: None,
        ..Config::default()
    };
    // One mutation mostly: with more, almost every mutant is refused and few get rendered.
    let mutations = prop_oneof![
        3 => prop::collection::vec(mutation(), 1..=1),
        1 => prop::collection::vec(mutation(), 2..=3),
    ];
    let strategy = (0..inputs.len(), mutations, any::<bool>());
    let counts = Counts::default();
    let start = Instant::now();
    let mut runner = TestRunner::new(config);
    let result = runner.run(&strategy, |(input, mutations, shade_back)| {
        let input = &inputs[input];
        let mut bytes = input.bytes.clone();
        for mutation in &mutations {
            apply(&mut bytes, mutation);
        }
        match input.kind {
            Kind::Scene => check_scene(folder.path(), &bytes, shade_back, &counts),
            Kind::Obj => check_obj(folder.path(), &bytes, shade_back, &counts),
        }
    });
    if let Err(error) = result {
        let (reason, (input, mutations, shade_back)) = match error {
            TestError::Fail(reason, value) => (reason.to_string(), value),
            TestError::Abort(reason) => panic!("mutation testing stopped: {reason}"),
        };
        let mut bytes = inputs[input].bytes.clone();
        for mutation in &mutations {
            apply(&mut bytes, mutation);
        }
        panic!(
            "{reason}\ninput {} with {mutations:?} (shade_back {shade_back}) gives:\n{}",
            inputs[input].name,
            bytes.escape_ascii()
        );
    }
    let (refused, rendered) = (counts.refused.get(), counts.rendered.get());
    // Straight to stderr, past the test harness's capture: CI logs show the count.
    let _ = writeln!(
        std::io::stderr(),
        "mutation: {} cases ({refused} refused with file:line:column, {rendered} rendered) \
         from {} inputs, seed {seed}, in {:.1} s",
        refused + rendered,
        inputs.len(),
        start.elapsed().as_secs_f64()
    );
    assert_eq!(
        refused + rendered,
        cases,
        "every case should have been counted once"
    );
    // A mutation that rarely breaks anything, or rarely leaves anything to render, would test
    // little: both outcomes must be common.
    assert!(refused > cases / 10 && rendered > cases / 10);
}

#[test]
fn every_input_is_valid_before_it_is_mutated() {
    let (inputs, folder) = inputs();
    let counts = Counts::default();
    for input in &inputs {
        let result = match input.kind {
            Kind::Scene => check_scene(folder.path(), &input.bytes, false, &counts),
            Kind::Obj => check_obj(folder.path(), &input.bytes, false, &counts),
        };
        result.unwrap();
        assert_eq!(counts.refused.get(), 0, "{} was refused", input.name);
    }
}

#[test]
fn mutations_do_what_they_say() {
    let mut text = b"Sphere { center 1 -2 3 }".to_vec();
    apply(&mut text, &Mutation::Swap(0, 3));
    assert_eq!(text, b"1 { center Sphere -2 3 }");
    apply(&mut text, &Mutation::Number(1, NUMBERS.len()));
    assert_eq!(text, b"1 { center Sphere 2 3 }");
    apply(&mut text, &Mutation::Number(2, 0));
    assert_eq!(text, b"1 { center Sphere 2 1e39 }");
    apply(&mut text, &Mutation::Delete(0));
    apply(&mut text, &Mutation::Duplicate(2));
    assert_eq!(text, b" { center Sphere Sphere 2 1e39 }");
    apply(&mut text, &Mutation::Insert(1, vec![0xff, 0]));
    apply(&mut text, &Mutation::Flip(0, 1));
    apply(&mut text, &Mutation::Truncate(5));
    assert_eq!(text, b"!\xff\x00{ ");
    apply(&mut text, &Mutation::Keyword(0, 0));
    assert_eq!(text, b"OrthographicCamera ");
}
