//! `check --vary SEED`: graded on scenes nobody has seen. Each line's scene is changed within
//! bounds that keep what the line tests (the camera orbits its subject by a few degrees,
//! directional lights turn by a few degrees, the colours of lights, the background and the
//! materials are scaled channel by channel), and raycast's render of the changed scene is the
//! reference. A renderer that prints pictures it memorised fails; a correct one passes as
//! before, since raycast matches the course's images.
//!
//! What is left alone, and why: positions of objects and point lights (objects touch, rest on
//! planes and cast shadows on each other: moving one changes what the line tests), the field of
//! view (objects at the frame's edge would leave it), and the reflective and transparent colours
//! (a bounce's weight decides, against `-weight`, whether a ray is traced at all). The filter
//! pictures of assignment 7 (`-render_filter`) do not depend on the scene, so they stay what
//! they were; its samples pictures show each sample's colour, and vary with the scene.
//!
//! Every change is a word of the scene's text replaced by another number: the rest of the file
//! (its layout, its meshes, its other numbers) stays byte for byte, and a teacher can diff the
//! varied scene against the original. The same seed and suite give the same scenes on every
//! system.

use glam::{DQuat, DVec3};
use rand_core::Rng;
use rand_pcg::Pcg32;
use std::path::{Path, PathBuf};

use super::CheckOptions;
use super::scratch::Scratch;
use super::suite::Suite;

/// How far the camera orbits its subject, in degrees (at least, at most).
const CAMERA_TURN: (f64, f64) = (1.0, 3.0);

/// How far the camera moves across its view, as a share of the view's width at its subject
/// (at least, at most): the subject moves in the frame, so that even a sphere the camera
/// orbits looks otherwise.
const CAMERA_SHIFT: (f64, f64) = (0.02, 0.04);

/// How far a directional light turns, in degrees (at least, at most).
const LIGHT_TURN: (f64, f64) = (2.0, 5.0);

/// The least factor a colour's channel is scaled by (the most is 1: a colour never grows past
/// what the course's scene clamps).
const LEAST_COLOUR_SCALE: f64 = 0.8;

/// A suite's copy with its scenes varied, in a scratch folder of its own.
pub struct VariedSuite {
    folder: Scratch,
    variation: Variation,
}

impl VariedSuite {
    /// Copies the suite at `original` (its `COMMANDS.txt`, `POINTS`, `CHOICES`, `GRADING` and
    /// `scenes/`, not its references) and varies every scene a line reads with `-input`.
    pub fn make(original: &Path, seed: u64) -> Result<VariedSuite, String> {
        let suite = Suite::read(original)?;
        let folder = Scratch::new()?;
        let root = folder.path();
        for file in ["COMMANDS.txt", "POINTS", "CHOICES", "GRADING"] {
            let from = original.join(file);
            if from.is_file() {
                std::fs::copy(&from, root.join(file))
                    .map_err(|e| format!("{}: {e}", from.display()))?;
            }
        }
        super::modes::copy_tree(&suite.scenes, &root.join("scenes"))?;
        let mut scenes: Vec<PathBuf> = suite
            .lines
            .iter()
            .filter_map(|line| {
                let at = line.args.iter().position(|a| a == "-input")?;
                line.args.get(at + 1).map(PathBuf::from)
            })
            .filter(|scene| super::run::inside(scene))
            .collect();
        scenes.sort();
        scenes.dedup();
        let mut varied = Vec::new();
        for scene in scenes {
            let path = root.join("scenes").join(&scene);
            // A scene that cannot be read is the renderer's to refuse, as it would be unvaried.
            let Ok(text) = std::fs::read_to_string(&path) else {
                continue;
            };
            let changed = vary_scene(&text, scene_seed(seed, &scene));
            if changed != text {
                std::fs::write(&path, changed).map_err(|e| format!("{}: {e}", path.display()))?;
                varied.push(scene);
            }
        }
        Ok(VariedSuite {
            folder,
            variation: Variation {
                seed,
                scenes: varied,
                from: original.to_path_buf(),
            },
        })
    }

    /// The varied suite's folder.
    pub fn path(&self) -> &Path {
        self.folder.path()
    }

    /// `options` grading this copy in place of the suite it was made from.
    pub fn options(&self, options: &CheckOptions) -> CheckOptions {
        CheckOptions {
            suite: self.path().to_path_buf(),
            vary: Some(self.variation.seed),
            varied: Some(self.variation.clone()),
            ..options.clone()
        }
    }

    /// Removes the copy; `Err` names what could not be removed.
    pub fn remove(self) -> Result<(), String> {
        self.folder.remove()
    }
}

/// The variation a run graded with.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Variation {
    /// The seed: `--vary SEED` makes the same scenes again.
    pub seed: u64,
    /// The scenes it changed, relative to the suite's `scenes/`.
    pub scenes: Vec<PathBuf>,
    /// The suite the varied copy was made from.
    pub from: PathBuf,
}

/// The folder of a report that holds the varied scenes.
pub const VARIED_FOLDER: &str = "varied";

impl Variation {
    /// As `summary.json` writes it.
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "seed": self.seed,
            "folder": VARIED_FOLDER,
            "scenes": self
                .scenes
                .iter()
                .map(|s| s.display().to_string())
                .collect::<Vec<_>>(),
        })
    }

    /// The variation a report's `summary.json` records (the suite it came from is not kept).
    pub fn from_json(value: &serde_json::Value) -> Option<Variation> {
        Some(Variation {
            seed: value["seed"].as_u64()?,
            scenes: value["scenes"]
                .as_array()?
                .iter()
                .map(|s| s.as_str().map(PathBuf::from))
                .collect::<Option<_>>()?,
            from: PathBuf::new(),
        })
    }

    /// Copies the changed scenes from `scenes` (a varied copy's `scenes/`, or a report's
    /// `varied/`) into `report/varied/`.
    pub fn copy_scenes(&self, scenes: &Path, report: &Path) -> Result<(), String> {
        for scene in &self.scenes {
            let target = report.join(VARIED_FOLDER).join(scene);
            if let Some(parent) = target.parent() {
                std::fs::create_dir_all(parent)
                    .map_err(|e| format!("{}: {e}", parent.display()))?;
            }
            std::fs::copy(scenes.join(scene), &target)
                .map_err(|e| format!("{}: {e}", target.display()))?;
        }
        Ok(())
    }

    /// One sentence for the terminal and the report's page.
    pub fn sentence(&self) -> String {
        format!(
            "graded on varied scenes (--vary {}): {} scene{} changed within bounds that keep what \
             each line tests, each picture compared with raycast's render of its varied scene",
            self.seed,
            self.scenes.len(),
            if self.scenes.len() == 1 { "" } else { "s" }
        )
    }
}

/// A student's own variation in a class graded with `--vary SEED`: the same for the same seed
/// and name, so that `--vary` with it makes that student's scenes again.
pub fn student_seed(seed: u64, student: &str) -> u64 {
    mix(seed, student.as_bytes())
}

/// The seed of one scene file's variation.
fn scene_seed(seed: u64, scene: &Path) -> u64 {
    mix(seed, scene.to_string_lossy().as_bytes())
}

/// FNV-1a over `bytes`, started from `seed`: stable on every system and release (the
/// standard library's hasher promises neither).
fn mix(seed: u64, bytes: &[u8]) -> u64 {
    let mut hash = 0xcbf2_9ce4_8422_2325_u64 ^ seed.wrapping_mul(0x9e37_79b9_7f4a_7c15);
    for &b in bytes {
        hash ^= u64::from(b);
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
    hash
}

/// A field of a block whose numbers may change: which block (counted in the file's order),
/// the block's kind, the field's keyword, and where its numbers are among the words.
struct Field<'a> {
    block: usize,
    kind: &'a str,
    keyword: &'a str,
    at: usize,
}

/// How many numbers follow each keyword that varies, in the blocks where it varies.
fn numbers_of(kind: &str, keyword: &str) -> Option<usize> {
    match (kind, keyword) {
        ("OrthographicCamera" | "PerspectiveCamera", "center" | "direction" | "up") => Some(3),
        ("OrthographicCamera", "size") | ("PerspectiveCamera", "angle") => Some(1),
        ("DirectionalLight", "direction" | "color") => Some(3),
        ("PointLight", "color") => Some(3),
        ("Background", "color" | "ambientLight") => Some(3),
        ("PhongMaterial" | "Material", "diffuseColor" | "specularColor") => Some(3),
        _ => None,
    }
}

/// `text`, a scene, with its camera, directional lights and colours varied by `seed`; the
/// text as it is where it is not a scene raycast reads (the renderer refuses it alike).
pub fn vary_scene(text: &str, seed: u64) -> String {
    if crate::parse::parse_scene(Path::new("scene.txt"), text).is_err() {
        return text.to_string();
    }
    let words = words_of(text);
    let mut fields = Vec::new();
    let mut open: Vec<(usize, &str)> = Vec::new();
    let mut blocks = 0;
    for (i, &(_, word)) in words.iter().enumerate() {
        match word {
            "{" => {
                // A byte-order mark (Notepad's) before the first block is no part of its name.
                let kind = i
                    .checked_sub(1)
                    .map_or("", |p| words[p].1.trim_start_matches('\u{feff}'));
                open.push((blocks, kind));
                blocks += 1;
            }
            "}" => {
                open.pop();
            }
            _ => {
                if let Some(&(block, kind)) = open.last()
                    && numbers_of(kind, word).is_some()
                {
                    fields.push(Field {
                        block,
                        kind,
                        keyword: word,
                        at: i + 1,
                    });
                }
            }
        }
    }
    let mut replaced: Vec<Option<String>> = vec![None; words.len()];
    let vector = |field: &Field| -> Option<DVec3> {
        let n = numbers_of(field.kind, field.keyword)?;
        let values: Vec<f64> = (field.at..field.at + n)
            .map(|k| words.get(k)?.1.parse::<f32>().ok().map(f64::from))
            .collect::<Option<_>>()?;
        Some(DVec3::from_slice(&values))
    };
    let mut write = |field: &Field, value: DVec3| {
        for (k, v) in value.to_array().into_iter().enumerate().take(3) {
            replaced[field.at + k] = Some(format!("{}", v as f32));
        }
    };
    for field in &fields {
        // Each field of each block draws from a stream of its own.
        let mut random = Pcg32::new(mix(seed, field.keyword.as_bytes()), field.block as u64);
        match (field.kind, field.keyword) {
            (_, "color" | "ambientLight" | "diffuseColor" | "specularColor") => {
                if let Some(colour) = vector(field) {
                    let scale = DVec3::new(
                        colour_scale(&mut random),
                        colour_scale(&mut random),
                        colour_scale(&mut random),
                    );
                    write(field, colour * scale);
                }
            }
            ("DirectionalLight", "direction") => {
                if let Some(direction) = vector(field).filter(|d| d.length() > 0.0) {
                    let turn = turn(&mut random, direction, LIGHT_TURN);
                    write(field, turn * direction);
                }
            }
            _ => {}
        }
    }
    // The camera orbits the point it looks at nearest the scene's origin: centre, direction
    // and up turn together, so the subject stays in the frame and up stays what it was to
    // the direction.
    let mut cameras: Vec<usize> = fields
        .iter()
        .filter(|f| f.kind.ends_with("Camera"))
        .map(|f| f.block)
        .collect();
    cameras.dedup();
    for camera in cameras {
        let field = |keyword: &str| {
            fields
                .iter()
                .find(|f| f.block == camera && f.keyword == keyword)
        };
        let (Some(centre), Some(direction), Some(up)) =
            (field("center"), field("direction"), field("up"))
        else {
            continue;
        };
        let (Some(c), Some(d), Some(u)) = (vector(centre), vector(direction), vector(up)) else {
            continue;
        };
        let Some(ahead) = d.try_normalize() else {
            continue;
        };
        let distance = (-c).dot(ahead).max(1.0);
        let pivot = c + ahead * distance;
        let mut random = Pcg32::new(mix(seed, b"camera"), camera as u64);
        let turn = turn(&mut random, ahead, CAMERA_TURN);
        // The view's width where the subject is: an orthographic camera's size, a perspective
        // camera's angle at the subject's distance.
        let width = match fields
            .iter()
            .find(|f| f.block == camera && numbers_of(f.kind, f.keyword) == Some(1))
        {
            Some(field) => words
                .get(field.at)
                .and_then(|w| w.1.parse::<f64>().ok())
                .map(|v| match field.kind {
                    "OrthographicCamera" => v,
                    _ => 2.0 * distance * (v.to_radians() / 2.0).tan(),
                }),
            None => None,
        }
        .filter(|w| w.is_finite() && *w > 0.0);
        let across = ahead.cross(u).try_normalize();
        let shift = match (width, across) {
            (Some(width), Some(across)) => {
                let square = across.cross(ahead);
                let towards = std::f64::consts::TAU * unit(&mut random);
                let by = width
                    * (CAMERA_SHIFT.0 + (CAMERA_SHIFT.1 - CAMERA_SHIFT.0) * unit(&mut random));
                (across * towards.cos() + square * towards.sin()) * by
            }
            _ => DVec3::ZERO,
        };
        write(centre, pivot + turn * (c - pivot + shift));
        write(direction, turn * d);
        write(up, turn * u);
    }
    let mut out = String::with_capacity(text.len() + 64);
    let mut from = 0;
    for (&(start, word), new) in words.iter().zip(&replaced) {
        if let Some(new) = new {
            out.push_str(&text[from..start]);
            out.push_str(new);
            from = start + word.len();
        }
    }
    out.push_str(&text[from..]);
    // Never a scene raycast would refuse where the original was read.
    if crate::parse::parse_scene(Path::new("scene.txt"), &out).is_err() {
        return text.to_string();
    }
    out
}

/// The words of `text` with where each starts, as the scene format splits them.
fn words_of(text: &str) -> Vec<(usize, &str)> {
    let mut words = Vec::new();
    let mut start = None;
    for (i, b) in text.bytes().enumerate() {
        match (b.is_ascii_whitespace(), start) {
            (true, Some(s)) => {
                words.push((s, &text[s..i]));
                start = None;
            }
            (false, None) => start = Some(i),
            _ => {}
        }
    }
    if let Some(s) = start {
        words.push((s, &text[s..]));
    }
    words
}

/// A number in [0, 1) from the generator.
fn unit(random: &mut Pcg32) -> f64 {
    f64::from(random.next_u32()) / 4_294_967_296.0
}

fn colour_scale(random: &mut Pcg32) -> f64 {
    LEAST_COLOUR_SCALE + (1.0 - LEAST_COLOUR_SCALE) * unit(random)
}

/// A rotation that turns `way` (not zero) by an angle between `degrees.0` and `degrees.1`,
/// towards a random side: about an axis at right angles to it, so that it is a turn, never a
/// roll about itself.
fn turn(random: &mut Pcg32, way: DVec3, degrees: (f64, f64)) -> DQuat {
    let way = way.normalize();
    // An axis uniform on the sphere, made square to `way`.
    let z = 2.0 * unit(random) - 1.0;
    let phi = std::f64::consts::TAU * unit(random);
    let r = (1.0 - z * z).max(0.0).sqrt();
    let any = DVec3::new(r * phi.cos(), r * phi.sin(), z);
    let axis = (any - way * any.dot(way))
        .try_normalize()
        .unwrap_or_else(|| way.any_orthonormal_vector());
    let angle = (degrees.0 + (degrees.1 - degrees.0) * unit(random)).to_radians();
    let sign = if unit(random) < 0.5 { -1.0 } else { 1.0 };
    DQuat::from_axis_angle(axis, sign * angle)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SCENE: &str = "\
PerspectiveCamera {
    center 0 1 10
    direction 0 -0.1 -1
    up 0 1 0
    angle 30
}
Lights {
    numLights 2
    DirectionalLight {
        direction -0.5 -0.5 -1
        color 0.9 0.9 0.9
    }
    PointLight {
        position 0 5 5
        color 0.5 0 0.5
        attenuation 1 0 0
    }
}
Background {
    color 0.2 0 0.6
    ambientLight 0.1 0.1 0.1
}
Materials {
    numMaterials 2
    PhongMaterial {
        diffuseColor 1 0 0
        specularColor 0.5 0.5 0.5
        exponent 20
        reflectiveColor 0.3 0.3 0.3
    }
    PhongMaterial {
        diffuseColor 0 1 0
        transparentColor 0.9 0.9 0.9
        indexOfRefraction 1.5
    }
}
Group {
    numObjects 2
    MaterialIndex 0
    Sphere {
        center 0 0 0
        radius 1
    }
    MaterialIndex 1
    Plane {
        normal 0 1 0
        offset -1
    }
}
";

    fn numbers_after(text: &str, keyword: &str) -> Vec<Vec<f64>> {
        let words = words_of(text);
        words
            .iter()
            .enumerate()
            .filter(|(_, w)| w.1 == keyword)
            .map(|(i, _)| {
                (i + 1..i + 4)
                    .filter_map(|k| words.get(k)?.1.parse().ok())
                    .collect()
            })
            .collect()
    }

    #[test]
    fn the_same_seed_varies_alike_and_another_seed_otherwise() {
        let once = vary_scene(SCENE, 7);
        assert_ne!(once, SCENE);
        assert_eq!(vary_scene(SCENE, 7), once);
        assert_ne!(vary_scene(SCENE, 8), once);
    }

    #[test]
    fn only_the_fields_that_keep_what_a_line_tests_change() {
        let varied = vary_scene(SCENE, 3);
        let before = words_of(SCENE);
        let after = words_of(&varied);
        assert_eq!(before.len(), after.len(), "{varied}");
        let mut changed_after = std::collections::BTreeSet::new();
        for (i, (a, b)) in before.iter().zip(&after).enumerate() {
            if a.1 != b.1 {
                // The keyword three words or fewer before the changed number.
                let keyword = (i.saturating_sub(3)..i)
                    .rev()
                    .map(|k| before[k].1)
                    .find(|w| w.parse::<f64>().is_err())
                    .unwrap();
                changed_after.insert(keyword);
            }
        }
        let expected: std::collections::BTreeSet<&str> = [
            "center",
            "direction",
            "up",
            "color",
            "ambientLight",
            "diffuseColor",
            "specularColor",
        ]
        .into();
        assert_eq!(changed_after, expected);
        // Positions, radii, the plane, the point light's place, the angle, mirror and glass
        // colours, the index: as they were.
        for keyword in [
            "position",
            "radius",
            "normal",
            "offset",
            "angle",
            "reflectiveColor",
            "transparentColor",
            "indexOfRefraction",
            "attenuation",
            "exponent",
        ] {
            assert_eq!(
                numbers_after(SCENE, keyword),
                numbers_after(&varied, keyword),
                "{keyword}"
            );
        }
        // The sphere's centre is the second `center`.
        assert_eq!(
            numbers_after(SCENE, "center")[1],
            numbers_after(&varied, "center")[1]
        );
        crate::parse::parse_scene(Path::new("scene.txt"), &varied).unwrap();
    }

    #[test]
    fn colours_shrink_by_at_most_a_fifth_channel_by_channel_and_zero_stays_zero() {
        for seed in 0..50 {
            let varied = vary_scene(SCENE, seed);
            for keyword in ["diffuseColor", "specularColor", "color", "ambientLight"] {
                for (was, is) in numbers_after(SCENE, keyword)
                    .iter()
                    .zip(numbers_after(&varied, keyword))
                {
                    for (w, v) in was.iter().zip(is) {
                        assert!(
                            v <= *w + 1e-6 && v >= w * LEAST_COLOUR_SCALE - 1e-6,
                            "{keyword} {w} became {v}"
                        );
                        if *w == 0.0 {
                            assert_eq!(v, 0.0);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn the_camera_orbits_its_subject_by_a_few_degrees_keeping_up_to_the_direction() {
        let angle = |a: DVec3, b: DVec3| a.angle_between(b).to_degrees();
        for seed in 0..50 {
            let varied = vary_scene(SCENE, seed);
            let v = |text: &str, keyword: &str| DVec3::from_slice(&numbers_after(text, keyword)[0]);
            let (c0, d0, u0) = (v(SCENE, "center"), v(SCENE, "direction"), v(SCENE, "up"));
            let (c1, d1, u1) = (
                v(&varied, "center"),
                v(&varied, "direction"),
                v(&varied, "up"),
            );
            let turned = angle(d0, d1);
            assert!(
                (CAMERA_TURN.0 - 1e-3..=CAMERA_TURN.1 + 1e-3).contains(&turned),
                "turned {turned}"
            );
            assert!((angle(d0, u0) - angle(d1, u1)).abs() < 1e-3);
            assert!((d0.length() - d1.length()).abs() < 1e-5);
            // The point it orbits is as far ahead as before, and off the view's axis by a
            // few hundredths of the view's width there (30 degrees).
            let distance = (-c0).dot(d0.normalize());
            let pivot = c0 + d0.normalize() * distance;
            let ahead = (pivot - c1).dot(d1.normalize());
            assert!((ahead - distance).abs() < 1e-4, "{ahead} {distance}");
            let off = (pivot - c1 - d1.normalize() * ahead).length();
            let width = 2.0 * distance * 15f64.to_radians().tan();
            assert!(
                (CAMERA_SHIFT.0 * width - 1e-4..=CAMERA_SHIFT.1 * width + 1e-4).contains(&off),
                "off the axis by {off} of {width}"
            );
            let light = |text: &str| DVec3::from_slice(&numbers_after(text, "direction")[1]);
            let light_turned = angle(light(SCENE), light(&varied));
            assert!(
                (LIGHT_TURN.0 - 1e-3..=LIGHT_TURN.1 + 1e-3).contains(&light_turned),
                "light turned {light_turned}"
            );
        }
    }

    #[test]
    fn a_scene_saved_by_notepad_varies_as_any_other() {
        let notepad = format!("\u{feff}{}", SCENE.replace('\n', "\r\n"));
        let varied = vary_scene(&notepad, 5);
        assert!(varied.starts_with("\u{feff}PerspectiveCamera {\r\n"));
        assert_eq!(
            varied.replace("\r\n", "\n").trim_start_matches('\u{feff}'),
            vary_scene(SCENE, 5)
        );
    }

    #[test]
    fn what_is_not_a_scene_is_left_as_it_is() {
        for text in ["", "Sphere {", "PerspectiveCamera { center 0 0 x }"] {
            assert_eq!(vary_scene(text, 1), text);
        }
    }

    #[test]
    fn a_students_seed_depends_on_the_seed_and_the_name() {
        assert_eq!(student_seed(1, "ada"), student_seed(1, "ada"));
        assert_ne!(student_seed(1, "ada"), student_seed(2, "ada"));
        assert_ne!(student_seed(1, "ada"), student_seed(1, "alan"));
    }
}
