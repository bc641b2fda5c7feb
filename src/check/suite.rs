//! A suite of the course's command lines: `COMMANDS.txt` (lines `raytracer ARGS`, the rest
//! comments), the `scenes/` they run in, and, where there is one, `reference/NAME.png` for each
//! image `NAME` they write.

use super::choices::{Accepted, Answer, CHOICES, Choice};
use std::path::{Path, PathBuf};

/// One command line of a suite.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Line {
    /// The line as the suite writes it, from `raytracer` on.
    pub command: String,
    /// The arguments after `raytracer`.
    pub args: Vec<String>,
    /// The images it writes: the argument's index and the file name given.
    pub outputs: Vec<(usize, String)>,
    /// Its place among the suite's command lines, from 0 (a shard keeps the suite's numbers).
    pub number: usize,
}

/// The options that only drive the course's OpenGL preview, with how many values each takes:
/// a student's renderer opens a window for them, and dies where there is no display.
pub const PREVIEW_OPTIONS: &[(&str, usize)] = &[("-gui", 0), ("-tessellation", 2), ("-gouraud", 0)];

impl Line {
    /// Whether the line names any of the preview options (`-gui`, `-tessellation`, `-gouraud`).
    pub fn has_preview_options(&self) -> bool {
        self.args
            .iter()
            .any(|a| PREVIEW_OPTIONS.iter().any(|(o, _)| a == o))
    }
}

/// `args` without the preview options and their values (the image is the same without them).
pub fn without_preview_options(args: &[String]) -> Vec<String> {
    let mut kept = Vec::with_capacity(args.len());
    let mut words = args.iter();
    while let Some(word) = words.next() {
        match PREVIEW_OPTIONS.iter().find(|(o, _)| word == o) {
            Some(&(_, values)) => {
                for _ in 0..values {
                    words.next();
                }
            }
            None => kept.push(word.clone()),
        }
    }
    kept
}

impl PictureKind {
    /// The option that writes it, as `summary.json` names the kind.
    pub fn option(self) -> &'static str {
        match self {
            PictureKind::Image => "-output",
            PictureKind::Normals => "-normals",
            PictureKind::Depth => "-depth",
            PictureKind::Samples => "-render_samples",
            PictureKind::Filter => "-render_filter",
        }
    }

    /// The kind [`PictureKind::option`] names.
    pub fn of_option(option: &str) -> Option<PictureKind> {
        [
            PictureKind::Image,
            PictureKind::Normals,
            PictureKind::Depth,
            PictureKind::Samples,
            PictureKind::Filter,
        ]
        .into_iter()
        .find(|k| k.option() == option)
    }
}

/// What kind of picture an option writes, which decides the advice a guess gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PictureKind {
    /// `-output`: the shaded picture.
    #[default]
    Image,
    /// `-normals`.
    Normals,
    /// `-depth`.
    Depth,
    /// `-render_samples`.
    Samples,
    /// `-render_filter`.
    Filter,
}

impl Line {
    /// The kind of the line's `k`-th image.
    pub fn picture_kind(&self, k: usize) -> PictureKind {
        let at = self.outputs[k].0;
        let flag = IMAGE_OPTIONS
            .iter()
            .find(|(flag, offset)| at >= *offset && self.args[at - offset] == *flag)
            .map_or("-output", |(flag, _)| flag);
        match flag {
            "-normals" => PictureKind::Normals,
            "-depth" => PictureKind::Depth,
            "-render_samples" => PictureKind::Samples,
            "-render_filter" => PictureKind::Filter,
            _ => PictureKind::Image,
        }
    }
}

/// A suite read from its folder.
#[derive(Debug, Clone, PartialEq)]
pub struct Suite {
    /// The suite's folder.
    pub root: PathBuf,
    /// Where the lines run: the scene files and meshes.
    pub scenes: PathBuf,
    /// The reference images found in `reference/` and the folders in it (such as
    /// `reference/a3/`), by image name, those at the top first; an image without one is graded
    /// against raycast's own render.
    pub references: Vec<(String, PathBuf)>,
    /// Every command line.
    pub lines: Vec<Line>,
    /// The points of the pictures the suite's `POINTS` file names; every other is worth one.
    pub points: Vec<(String, f64)>,
    /// The open questions the suite's `CHOICES` file pins to one answer.
    pub pinned: Vec<Pin>,
    /// Whether a picture written whole before the renderer crashed is graded by the picture
    /// alone (its `GRADING` file says `crash_at_exit picture`); by default the line fails.
    pub picture_alone_after_crash: bool,
}

/// An open question a suite pins to one answer (its `CHOICES` file: a line `QUESTION ANSWER`,
/// ANSWER `raycast` for raycast's own): only that answer passes, and its render is the
/// reference of the lines it changes.
#[derive(Debug, Clone, Copy)]
pub struct Pin {
    /// The question.
    pub choice: &'static Choice,
    /// Its answer: `None` for raycast's own.
    pub answer: Option<&'static Answer>,
}

// Questions and answers are known by their names.
impl PartialEq for Pin {
    fn eq(&self, other: &Pin) -> bool {
        self.choice.name == other.choice.name
            && self.answer.map(|a| a.name) == other.answer.map(|a| a.name)
    }
}

/// The largest `COMMANDS.txt` check reads (the course's longest is 12 KiB).
pub const MAX_COMMANDS_BYTES: u64 = 1 << 20;

/// The most command lines a suite may have (the course's largest has 168).
pub const MAX_LINES: usize = 10_000;

/// The most pictures one line may write (the course's write at most three).
pub const MAX_OUTPUTS: usize = 8;

/// Options that name an image file, and which of their values it is.
const IMAGE_OPTIONS: [(&str, usize); 5] = [
    ("-output", 1),
    ("-normals", 1),
    ("-depth", 3),
    ("-render_samples", 1),
    ("-render_filter", 1),
];

impl Suite {
    /// Reads `root/COMMANDS.txt` and checks that `root/scenes` exists. A suite is bounded: at
    /// most 1 MiB of `COMMANDS.txt`, 10,000 lines, 8 pictures a line.
    pub fn read(root: &Path) -> Result<Suite, String> {
        use std::io::Read;
        let commands = root.join("COMMANDS.txt");
        let cannot = |e: std::io::Error| format!("{}: cannot read: {e}", commands.display());
        let mut text = String::new();
        std::fs::File::open(&commands)
            .map_err(cannot)?
            .take(MAX_COMMANDS_BYTES + 1)
            .read_to_string(&mut text)
            .map_err(cannot)?;
        if text.len() as u64 > MAX_COMMANDS_BYTES {
            return Err(format!(
                "{}: more than {} MiB: not a suite's list of command lines",
                commands.display(),
                MAX_COMMANDS_BYTES >> 20
            ));
        }
        let scenes = root.join("scenes");
        if !scenes.is_dir() {
            return Err(format!(
                "{}: no scenes/ folder beside COMMANDS.txt",
                root.display()
            ));
        }
        let references = root.join("reference");
        let mut lines: Vec<Line> = text.lines().filter_map(parse_line).collect();
        for (number, line) in lines.iter_mut().enumerate() {
            line.number = number;
        }
        if lines.len() > MAX_LINES {
            return Err(format!(
                "{}: {} command lines, more than the {MAX_LINES} a suite may have",
                commands.display(),
                lines.len()
            ));
        }
        if let Some(line) = lines.iter().find(|l| l.outputs.len() > MAX_OUTPUTS) {
            return Err(format!(
                "{}: a line writes {} pictures, more than the {MAX_OUTPUTS} a line may: {}",
                commands.display(),
                line.outputs.len(),
                line.command.chars().take(200).collect::<String>()
            ));
        }
        if lines.is_empty() {
            return Err(format!(
                "{}: no command lines (lines that start with 'raytracer ')",
                commands.display()
            ));
        }
        let points = read_points(&root.join("POINTS"), &lines)?;
        let pinned = read_pins(&root.join("CHOICES"))?;
        let picture_alone_after_crash = read_grading(&root.join("GRADING"))?;
        Ok(Suite {
            root: root.to_path_buf(),
            scenes,
            references: reference_files(&references),
            lines,
            points,
            pinned,
            picture_alone_after_crash,
        })
    }

    /// How many pictures the suite's lines write, and the points they are worth together.
    pub fn pictures_and_points(&self) -> (usize, f64) {
        let names: Vec<String> = self
            .lines
            .iter()
            .flat_map(|line| line.outputs.iter().map(|(_, name)| image_name(name)))
            .collect();
        let points = names.iter().map(|name| self.points(name)).sum();
        (names.len(), points)
    }

    /// The points a picture named `name` is worth.
    pub fn points(&self, name: &str) -> f64 {
        self.points
            .iter()
            .find(|(known, _)| known == name)
            .map_or(1.0, |&(_, points)| points)
    }

    /// The reference image of the image named `name` (without its extension), if the suite
    /// has one.
    pub fn reference(&self, name: &str) -> Option<PathBuf> {
        self.references
            .iter()
            .find(|(known, _)| known == name)
            .map(|(_, path)| path.clone())
    }
}

/// The lines of one of a suite's settings files (`POINTS`, `CHOICES`, `GRADING`) that say
/// something, each with where it is (`PATH line N`) for messages: `#` starts a comment; no
/// file, no lines.
fn settings(path: &Path) -> Vec<(String, String)> {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    text.lines()
        .enumerate()
        .filter_map(|(number, line)| {
            let text = line.split('#').next().unwrap_or("").trim();
            (!text.is_empty()).then(|| {
                (
                    format!("{} line {}", path.display(), number + 1),
                    text.to_string(),
                )
            })
        })
        .collect()
}

/// Reads a suite's `POINTS` file, if it has one: a line `NAME POINTS` for each picture worth
/// other than one (NAME as the picture's file name without its extension; `#` starts a
/// comment).
fn read_points(path: &Path, lines: &[Line]) -> Result<Vec<(String, f64)>, String> {
    let mut points = Vec::new();
    for (at, text) in settings(path) {
        let words: Vec<&str> = text.split_whitespace().collect();
        let [name, value] = words[..] else {
            return Err(format!("{}: expected 'NAME POINTS', found '{text}'", at));
        };
        let value: f64 = value
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite() && *v >= 0.0)
            .ok_or_else(|| format!("{}: '{value}' is not a number of points (0 or more)", at))?;
        let known = lines
            .iter()
            .any(|l| l.outputs.iter().any(|(_, n)| image_name(n) == name));
        if !known {
            return Err(format!(
                "{}: no line of COMMANDS.txt writes a picture named '{name}'",
                at
            ));
        }
        points.push((name.to_string(), value));
    }
    Ok(points)
}

/// Reads a suite's `GRADING` file, if it has one: how a run is graded where the course leaves
/// it to the teacher. One setting so far, `crash_at_exit picture` (a picture written whole
/// before a crash is graded alone) or `crash_at_exit line` (the line fails: the default).
fn read_grading(path: &Path) -> Result<bool, String> {
    let mut picture_alone = false;
    for (at, text) in settings(path) {
        let words: Vec<&str> = text.split_whitespace().collect();
        picture_alone = match words[..] {
            ["crash_at_exit", "picture"] => true,
            ["crash_at_exit", "line"] => false,
            _ => {
                return Err(format!(
                    "{at}: expected 'crash_at_exit picture' or 'crash_at_exit line', found \
                     '{text}'"
                ));
            }
        };
    }
    Ok(picture_alone)
}

/// Reads a suite's `CHOICES` file, if it has one: a line `QUESTION ANSWER` for each open
/// question a class pins (`gaussian_cut raycast`, `checkerboard_parity checker_swapped`; `#`
/// starts a comment).
fn read_pins(path: &Path) -> Result<Vec<Pin>, String> {
    let mut pins: Vec<Pin> = Vec::new();
    for (at, text) in settings(path) {
        let words: Vec<&str> = text.split_whitespace().collect();
        let [question, answer] = words[..] else {
            return Err(format!(
                "{}: expected 'QUESTION ANSWER', found '{text}'",
                at
            ));
        };
        let questions = || {
            CHOICES
                .iter()
                .filter(|c| matches!(c.accepted, Accepted::Answers(_)))
                .map(|c| c.name)
                .collect::<Vec<_>>()
                .join(", ")
        };
        let choice = CHOICES.iter().find(|c| c.name == question).ok_or_else(|| {
            format!(
                "{}: no open question '{question}' (one of {})",
                at,
                questions()
            )
        })?;
        let Accepted::Answers(answers) = &choice.accepted else {
            return Err(format!(
                "{}: '{question}' has no answers to pin (one of {})",
                at,
                questions()
            ));
        };
        let answer = match answer {
            "raycast" => None,
            name => Some(answers.iter().find(|a| a.name == name).ok_or_else(|| {
                let names: Vec<&str> = answers.iter().map(|a| a.name).collect();
                format!(
                    "{}: '{name}' is no answer to {question} (raycast, {})",
                    at,
                    names.join(", ")
                )
            })?),
        };
        if pins.iter().any(|p| p.choice.name == question) {
            return Err(format!("{}: {question} is pinned twice", at));
        }
        pins.push(Pin { choice, answer });
    }
    Ok(pins)
}

/// The PNG files of `folder` and of the folders in it, by name without extension; those at the
/// top first, then each folder's in name order.
fn reference_files(folder: &Path) -> Vec<(String, PathBuf)> {
    let pngs = |dir: &Path| -> (Vec<(String, PathBuf)>, Vec<PathBuf>) {
        let mut files = Vec::new();
        let mut folders = Vec::new();
        for entry in std::fs::read_dir(dir).into_iter().flatten().flatten() {
            let path = entry.path();
            if path.is_dir() {
                folders.push(path);
            } else if path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("png"))
            {
                let name = image_name(&path.to_string_lossy());
                files.push((name, path));
            }
        }
        files.sort();
        folders.sort();
        (files, folders)
    };
    let (mut found, folders) = pngs(folder);
    for inner in folders {
        found.extend(pngs(&inner).0);
    }
    found
}

/// A line of `COMMANDS.txt`, or `None` for a comment or a line that writes no image. The
/// course's lists annotate lines after `->` or `(preview only)`: that part is not the command.
pub fn parse_line(text: &str) -> Option<Line> {
    let text = text.trim();
    let rest = text.strip_prefix("raytracer ")?;
    let rest = rest.split("->").next().unwrap_or(rest);
    let rest = rest.split("(preview only)").next().unwrap_or(rest);
    let args: Vec<String> = rest.split_whitespace().map(String::from).collect();
    let mut outputs = Vec::new();
    for (i, arg) in args.iter().enumerate() {
        if let Some(&(_, offset)) = IMAGE_OPTIONS.iter().find(|(name, _)| name == arg)
            && let Some(name) = args.get(i + offset)
        {
            outputs.push((i + offset, name.clone()));
        }
    }
    if outputs.is_empty() {
        return None;
    }
    Some(Line {
        number: 0,
        command: format!("raytracer {}", args.join(" ")),
        args,
        outputs,
    })
}

/// The assignment a picture belongs to, from its name: `output2_01`, `depth3_08` and
/// `normals1_05` are A2, A3 and A1; a name without such a number is "other".
pub fn assignment(name: &str) -> String {
    let digits: String = name
        .trim_start_matches(|c: char| c.is_ascii_alphabetic())
        .chars()
        .take_while(char::is_ascii_digit)
        .collect();
    let numbered = name.contains('_') && !digits.is_empty();
    if numbered {
        format!("A{digits}")
    } else {
        "other".to_string()
    }
}

/// The name an image is graded under: its file name without the extension.
pub fn image_name(file: &str) -> String {
    let name = Path::new(file)
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| file.to_string());
    match name.rsplit_once('.') {
        Some((stem, _)) if !stem.is_empty() => stem.to_string(),
        _ => name,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_image_knows_the_option_that_names_it() {
        let line = parse_line(
            "raytracer -input s.txt -size 9 9 -normals n.tga -depth 9 11 d.tga -output o.tga \
             -render_samples s.tga 4 -render_filter f.tga 4",
        )
        .unwrap();
        let kinds: Vec<PictureKind> = (0..5).map(|k| line.picture_kind(k)).collect();
        assert_eq!(
            kinds,
            [
                PictureKind::Normals,
                PictureKind::Depth,
                PictureKind::Image,
                PictureKind::Samples,
                PictureKind::Filter
            ]
        );
    }

    #[test]
    fn lines_with_their_images() {
        let line = parse_line(
            "raytracer -input s.txt -size 200 200 -output o.tga -depth 9 11 d.tga -normals n.tga",
        )
        .unwrap();
        assert_eq!(
            line.outputs,
            [
                (6, "o.tga".into()),
                (10, "d.tga".into()),
                (12, "n.tga".into())
            ]
        );
        let annotated = parse_line(
            "raytracer -input a.txt -size 9 9 -render_filter f.tga 20 -box_filter 0.5   -> x.png",
        )
        .unwrap();
        assert_eq!(annotated.outputs, [(6, "f.tga".into())]);
        assert_eq!(
            annotated.command,
            "raytracer -input a.txt -size 9 9 -render_filter f.tga 20 -box_filter 0.5"
        );
        assert_eq!(parse_line("# a comment"), None);
        assert_eq!(
            parse_line("raytracer -input s.txt -size 200 200 -gui (preview only)"),
            None
        );
        assert_eq!(image_name("output3_01.tga"), "output3_01");
        assert_eq!(image_name("out/a.b.png"), "a.b");
    }
}
