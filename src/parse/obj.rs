//! Wavefront .obj reading: positions and faces, the parts a ray caster needs.
//!
//! The course's files hold only `v x y z` and `f a b c` lines, but users bring meshes exported by
//! every tool there is, so this reads real files: comments, `f a/b/c` and `a//c` references,
//! polygons (split into fans), negative (relative) indices, and statements that carry no geometry
//! (normals, texture coordinates, groups, materials), which it skips. Hand-written rather than
//! `tobj`, for two reasons: every error names its line and column, and speed: the 69k-triangle
//! bunny is read in about 15 ms, in a whole render of under 200.

use std::path::Path;

use glam::Vec3;
use rayon::prelude::*;

use crate::error::Diagnostic;
use crate::error::Span;
use crate::parse::{MAX_MAGNITUDE, NUMBER_IN_RANGE, describe};

/// A triangle soup: vertex positions and, per triangle, three indices into them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ObjMesh {
    /// The `v` lines in the file's order; a w or a vertex colour after x, y and z is dropped.
    pub positions: Vec<Vec3>,
    /// 0-based indices into `positions`, all in range; a face of more than three corners is
    /// split into a fan about its first.
    pub triangles: Vec<[u32; 3]>,
}

/// Statements that are valid .obj but say nothing about the surface a ray hits.
#[rustfmt::skip]
const SKIPPED: &[&[u8]] = &[
    b"vn", b"vt", b"vp", b"g", b"o", b"s", b"usemtl", b"mtllib", b"l", b"p", b"mg", b"lod",
    b"usemap", b"maplib", b"shadow_obj", b"trace_obj", b"bevel", b"c_interp", b"d_interp",
    b"cstype", b"deg", b"bmat", b"step", b"curv", b"curv2", b"surf", b"parm", b"trim", b"hole",
    b"scrv", b"sp", b"end", b"con", b"ctech", b"stech", b"call", b"csh",
];

/// Files at least this long are read in pieces on rayon's threads.
const PARALLEL_BYTES: usize = 1 << 20;

/// Reads an .obj file's bytes; `path` only names the file in messages. A face may use only the
/// vertices defined above it, and every error carries a line and column.
///
/// A big file is cut at line ends into pieces read in parallel: a first pass counts each
/// piece's lines and `v` statements, which tells every piece the number of its first line and
/// how many vertices lie above it, so that each reads its faces' indices, and words its errors,
/// exactly as one reading of the whole file would. The error reported is the first in the file.
/// A byte-order mark at its start (Notepad's UTF-8) is no part of the mesh.
pub fn parse_obj(path: &Path, bytes: &[u8]) -> Result<ObjMesh, Diagnostic> {
    let mut mark = [0; 4];
    let mark = super::parser::BYTE_ORDER_MARK
        .encode_utf8(&mut mark)
        .as_bytes();
    let bytes = bytes.strip_prefix(mark).unwrap_or(bytes);
    let threads = rayon::current_num_threads();
    if threads == 1 || bytes.len() < PARALLEL_BYTES {
        // No line makes more than one vertex.
        let lines = memchr::memchr_iter(b'\n', bytes).count() + 1;
        return parse_piece(
            path,
            bytes,
            Start::FILE,
            Room {
                positions: lines,
                triangles: lines,
            },
        );
    }
    let pieces = split_at_lines(bytes, 4 * threads);
    let counts: Vec<(u32, usize)> = pieces
        .par_iter()
        .map(|piece| {
            let lines = memchr::memchr_iter(b'\n', piece).count();
            (lines as u32, vertex_lines(piece))
        })
        .collect();
    let mut starts = Vec::with_capacity(pieces.len());
    let mut start = Start::FILE;
    for &(lines, vertices) in &counts {
        starts.push(start);
        start = Start {
            line: start.line + lines,
            vertices: start.vertices + vertices,
        };
    }
    let parsed: Vec<Result<ObjMesh, Diagnostic>> = pieces
        .par_iter()
        .zip(starts)
        .zip(&counts)
        .map(|((piece, start), &(lines, vertices))| {
            // The first pass's counts: the vertices exactly, a triangle a line at most.
            parse_piece(
                path,
                piece,
                start,
                Room {
                    positions: vertices,
                    triangles: lines as usize + 1,
                },
            )
        })
        .collect();
    let parsed = parsed
        .into_iter()
        .collect::<Result<Vec<ObjMesh>, Diagnostic>>()?;
    // Each array made once, at its size: grown piece by piece, every doubling was a copy into
    // fresh pages.
    let mut mesh = ObjMesh {
        positions: Vec::with_capacity(parsed.iter().map(|p| p.positions.len()).sum()),
        triangles: Vec::with_capacity(parsed.iter().map(|p| p.triangles.len()).sum()),
    };
    for piece in parsed {
        mesh.positions.extend_from_slice(&piece.positions);
        mesh.triangles.extend_from_slice(&piece.triangles);
    }
    Ok(mesh)
}

/// Where a piece of a file begins: the number of its first line, and the vertices defined in
/// the file above it.
#[derive(Debug, Clone, Copy)]
struct Start {
    line: u32,
    vertices: usize,
}

impl Start {
    const FILE: Start = Start {
        line: 1,
        vertices: 0,
    };
}

/// The room a piece's arrays are made with: enough that they are rarely grown (each doubling
/// was a copy into fresh pages). A line makes one triangle unless it is a face of four corners
/// or more; room left over is never touched.
#[derive(Debug, Clone, Copy)]
struct Room {
    positions: usize,
    triangles: usize,
}

/// `bytes` in about `count` pieces of similar length, each (but the last) ending with a newline.
fn split_at_lines(bytes: &[u8], count: usize) -> Vec<&[u8]> {
    let target = bytes.len().div_ceil(count).max(1);
    let mut pieces = Vec::with_capacity(count);
    let mut rest = bytes;
    while !rest.is_empty() {
        let end = match memchr::memchr(b'\n', &rest[target.min(rest.len() - 1)..]) {
            Some(newline) => target.min(rest.len() - 1) + newline + 1,
            None => rest.len(),
        };
        let (piece, tail) = rest.split_at(end);
        pieces.push(piece);
        rest = tail;
    }
    pieces
}

/// How many lines of `piece` are `v` statements (those that, read, define one vertex each).
fn vertex_lines(piece: &[u8]) -> usize {
    piece
        .split(|&b| b == b'\n')
        .filter(|line| {
            let (_, mut words) = statement(line);
            words.next().is_some_and(|(keyword, _)| keyword == b"v")
        })
        .count()
}

/// Reads one piece of a file, which begins at `start`.
///
/// One function, long: the per-line loop is the reader's hot path (a 100k-triangle mesh in
/// about 9 ms), with the face buffer and the position in the file kept across lines; each
/// statement's arms are short and read top to bottom.
fn parse_piece(path: &Path, bytes: &[u8], start: Start, room: Room) -> Result<ObjMesh, Diagnostic> {
    let mut mesh = ObjMesh {
        positions: Vec::with_capacity(room.positions),
        triangles: Vec::with_capacity(room.triangles),
    };
    let mut face: Vec<u32> = Vec::new();
    let mut rest = bytes;
    for line_number in start.line.. {
        let line = match memchr::memchr(b'\n', rest) {
            Some(end) => {
                let line = &rest[..end];
                rest = &rest[end + 1..];
                line
            }
            None if rest.is_empty() && line_number > start.line => break,
            None => std::mem::take(&mut rest),
        };
        let (content, mut words) = statement(line);
        let Some((keyword, keyword_at)) = words.next() else {
            continue;
        };
        let at = |offset: usize| Span::new(line_number, column(line, offset));
        match keyword {
            b"v" => {
                let mut xyz = [0.0f32; 3];
                for value in &mut xyz {
                    let Some((word, offset)) = words.next() else {
                        let end = content.trim_ascii_end().len();
                        return Err(Diagnostic::expected(
                            path,
                            at(end),
                            "a coordinate",
                            "end of line",
                        ));
                    };
                    *value = parse_coordinate(word).map_err(|expected| {
                        Diagnostic::expected(path, at(offset), expected, &show(word))
                    })?;
                }
                // A fourth value (w) or three more (a vertex colour) may follow; they do not
                // move the vertex, but they must still be numbers.
                for (word, offset) in words.by_ref() {
                    if let Err(expected) = parse_coordinate(word) {
                        let expected = match expected {
                            NOT_A_NUMBER => "a number or end of line",
                            out_of_range => out_of_range,
                        };
                        return Err(Diagnostic::expected(
                            path,
                            at(offset),
                            expected,
                            &show(word),
                        ));
                    }
                }
                mesh.positions.push(Vec3::from(xyz));
            }
            b"f" => {
                face.clear();
                let defined = start.vertices + mesh.positions.len();
                for (word, offset) in words.by_ref() {
                    let index = vertex_index(word, defined).ok_or_else(|| {
                        let expected = match defined {
                            0 => "a vertex defined before this face".to_string(),
                            n => format!("a vertex index from 1 to {n} (or -{n} to -1)"),
                        };
                        Diagnostic::expected(path, at(offset), &expected, &show(word))
                    })?;
                    face.push(index);
                }
                if face.len() < 3 {
                    let end = content.trim_ascii_end().len();
                    return Err(Diagnostic::expected(
                        path,
                        at(end),
                        "at least three vertices in a face",
                        &format!("{} and end of line", face.len()),
                    ));
                }
                for i in 1..face.len() - 1 {
                    mesh.triangles.push([face[0], face[i], face[i + 1]]);
                }
            }
            _ if SKIPPED.contains(&keyword) => {}
            _ => {
                return Err(Diagnostic::expected(
                    path,
                    at(keyword_at),
                    "an .obj statement (v, f, vn, vt, g, o, s, usemtl, mtllib, or # for a comment)",
                    &show(keyword),
                ));
            }
        }
    }
    Ok(mesh)
}

const NOT_A_NUMBER: &str = "a number";

/// A coordinate, or what was expected instead. The scene's bound holds here too: a mesh is
/// intersected in its own space, with the same single-precision products as any shape.
fn parse_coordinate(word: &[u8]) -> Result<f32, &'static str> {
    let value = match short_decimal(word) {
        Some(value) => value,
        None => {
            let text = std::str::from_utf8(word).map_err(|_| NOT_A_NUMBER)?;
            // Read as f32 directly: through f64 it would be rounded twice, now and then off by
            // an ulp.
            text.parse().map_err(|_| NOT_A_NUMBER)?
        }
    };
    // NaN fails the comparison too.
    if (value as f64).abs() <= MAX_MAGNITUDE {
        Ok(value)
    } else {
        Err(NUMBER_IN_RANGE)
    }
}

/// A plain decimal (`-0.0390041`, `93.87400100000001`) read without `str::parse`, with the same
/// result. Its digits, read as an integer, and the power of ten it is divided by are both exact
/// (in f32 below 2^24 and 10^10, else in f64 below 2^53 and 10^22), so one division rounds
/// correctly (Clinger's fast path). Through f64 the quotient is rounded twice, to f64 and then to
/// f32, which for one division gives the once-rounded f32 all the same: f64 carries more than
/// twice f32's precision plus two bits (Figueroa). Most coordinates in mesh files are of this
/// kind; anything else returns `None`.
fn short_decimal(word: &[u8]) -> Option<f32> {
    const POWERS: [f32; 11] = [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10];
    const LONG_POWERS: [f64; 23] = [
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
        1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
    ];
    let (negative, rest) = match word {
        [b'-', rest @ ..] => (true, rest),
        [b'+', rest @ ..] => (false, rest),
        _ => (false, word),
    };
    let (whole, fraction) = match memchr::memchr(b'.', rest) {
        Some(dot) => (&rest[..dot], &rest[dot + 1..]),
        None => (rest, &rest[..0]),
    };
    if whole.is_empty() && fraction.is_empty() || fraction.len() >= LONG_POWERS.len() {
        return None;
    }
    let mut digits: u64 = 0;
    for &b in whole.iter().chain(fraction) {
        if !b.is_ascii_digit() {
            return None;
        }
        digits = digits * 10 + u64::from(b - b'0');
        if digits >= 1 << 53 {
            return None;
        }
    }
    let magnitude = if digits < 1 << 24 && fraction.len() < POWERS.len() {
        digits as f32 / POWERS[fraction.len()]
    } else {
        (digits as f64 / LONG_POWERS[fraction.len()]) as f32
    };
    Some(if negative { -magnitude } else { magnitude })
}

/// The position index of one face corner (`i`, `i/t`, `i//n` or `i/t/n`), made 0-based.
fn vertex_index(word: &[u8], vertex_count: usize) -> Option<u32> {
    let position = word.split(|&b| b == b'/').next()?;
    // Read by hand: two thirds of a mesh file's numbers are these, and `str::parse` wants the
    // bytes checked as UTF-8 first.
    let (negative, digits) = match position {
        [b'-', rest @ ..] => (true, rest),
        [b'+', rest @ ..] => (false, rest),
        _ => (false, position),
    };
    if digits.is_empty() || digits.len() > 18 || !digits.iter().all(u8::is_ascii_digit) {
        return None;
    }
    let magnitude = digits
        .iter()
        .fold(0i64, |n, &d| n * 10 + i64::from(d - b'0'));
    let index = if negative { -magnitude } else { magnitude };
    let count = vertex_count as i64;
    let zero_based = if (1..=count).contains(&index) {
        index - 1
    } else if (-count..=-1).contains(&index) {
        count + index
    } else {
        return None;
    };
    Some(zero_based as u32)
}

/// A word as a message quotes it; bytes that are not UTF-8 are shown as `\xff` escapes, since a
/// replacement character would hide which byte is at fault.
fn show(word: &[u8]) -> String {
    match std::str::from_utf8(word) {
        Ok(text) => describe(text),
        Err(_) => {
            const LIMIT: usize = 40;
            let more = if word.len() > LIMIT { "…" } else { "" };
            format!("'{}{more}'", word[..word.len().min(LIMIT)].escape_ascii())
        }
    }
}

/// The character column of a byte offset, counted from 1.
fn column(line: &[u8], offset: usize) -> u32 {
    crate::parse::column_after(&line[..offset])
}

/// A line without its comment, and the words of what is left.
fn statement(line: &[u8]) -> (&[u8], Words<'_>) {
    let content = match memchr::memchr(b'#', line) {
        Some(hash) => &line[..hash],
        None => line,
    };
    (
        content,
        Words {
            line: content,
            pos: 0,
        },
    )
}

/// Whitespace-separated words of one line, with their byte offsets.
struct Words<'a> {
    line: &'a [u8],
    pos: usize,
}

impl<'a> Iterator for Words<'a> {
    type Item = (&'a [u8], usize);

    fn next(&mut self) -> Option<Self::Item> {
        let line = self.line;
        while self.pos < line.len() && line[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        if self.pos == line.len() {
            return None;
        }
        let start = self.pos;
        while self.pos < line.len() && !line[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        Some((&line[start..self.pos], start))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<ObjMesh, String> {
        parse_obj(Path::new("m.obj"), text.as_bytes()).map_err(|e| e.to_string())
    }

    /// A file of over a megabyte in every form the reader knows: comments, skipped statements,
    /// blank lines, `a/b/c` corners, polygons, negative indices reaching back a long way.
    fn big_obj() -> String {
        let mut text = String::from("# big\nmtllib x.mtl\n");
        for i in 0..40_000 {
            let x = i as f32 * 0.001;
            text += &format!("v {x} {} -{}.5 # vertex {i}\n", i % 7, i % 11);
            if i % 3 == 0 {
                text += "vn 0 1 0\n\n";
            }
            if i >= 3 {
                text += &format!("f {} -2 {}/1/1\n", i - 1, i + 1);
            }
            if i % 5 == 4 {
                text += "f -1 -3 -4 -5\ng part\n";
            }
        }
        text
    }

    fn parse_on(threads: usize, text: &str) -> Result<ObjMesh, String> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| parse(text))
    }

    #[test]
    fn a_big_file_read_in_pieces_is_read_as_in_one() {
        let text = big_obj();
        assert!(text.len() >= PARALLEL_BYTES, "{} bytes", text.len());
        let one = parse_on(1, &text).unwrap();
        assert_eq!(one.positions.len(), 40_000);
        assert!(one.triangles.len() > 40_000);
        for threads in [2, 3, 8] {
            assert_eq!(
                parse_on(threads, &text).as_ref(),
                Ok(&one),
                "{threads} threads"
            );
        }
    }

    #[test]
    fn a_big_files_first_error_is_named_as_in_one_reading() {
        let text = big_obj();
        // Two faults far apart: the first in the file is the one named, with its line.
        let lines: Vec<&str> = text.lines().collect();
        let (early, late) = (lines.len() * 2 / 3, lines.len() - 10);
        let mut broken: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
        broken[early] = "f 1 2 99999".into();
        broken[late] = "v 1 2 x".into();
        let broken = broken.join("\n");
        let one = parse_on(1, &broken).unwrap_err();
        assert!(one.starts_with(&format!("m.obj:{}:", early + 1)), "{one}");
        for threads in [2, 5] {
            assert_eq!(
                parse_on(threads, &broken),
                Err(one.clone()),
                "{threads} threads"
            );
        }
    }

    #[test]
    fn short_decimals_read_exactly_as_str_parse_reads_them() {
        let mut seed = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let mut fast = 0;
        for _ in 0..200_000 {
            let r = next();
            let whole = r % 100_000;
            let places = (r >> 20) % 9;
            let fraction = (r >> 24) % 10u64.pow(places as u32).max(1);
            let sign = if r >> 63 == 1 { "-" } else { "" };
            let text = match places {
                0 => format!("{sign}{whole}"),
                p => format!("{sign}{whole}.{fraction:0width$}", width = p as usize),
            };
            let expected: f32 = text.parse().unwrap();
            if let Some(value) = short_decimal(text.as_bytes()) {
                assert_eq!(value.to_bits(), expected.to_bits(), "{text}");
                fast += 1;
            }
        }
        assert!(fast > 50_000, "only {fast} took the fast path");
        // Long ones (as exporters write them: `93.87400100000001`), through f64.
        let mut long = 0;
        for _ in 0..200_000 {
            let r = next();
            let whole = r % 1_000_000;
            let places = 6 + (r >> 20) % 14;
            let fraction = next() % 10u64.pow(places as u32);
            let sign = if r >> 63 == 1 { "-" } else { "" };
            let text = format!("{sign}{whole}.{fraction:0width$}", width = places as usize);
            let expected: f32 = text.parse().unwrap();
            if let Some(value) = short_decimal(text.as_bytes()) {
                assert_eq!(value.to_bits(), expected.to_bits(), "{text}");
                long += 1;
            }
        }
        assert!(long > 50_000, "only {long} long ones took the fast path");
        // Halfway between two floats: rounded once, to even.
        for text in ["16777217", "16777219", "0.16777217", "33554435"] {
            let expected: f32 = text.parse().unwrap();
            assert_eq!(short_decimal(text.as_bytes()), Some(expected), "{text}");
        }
        // Just off halfway, in more digits than f64 holds exactly: left to `str::parse`.
        assert_eq!(short_decimal(b"16777217.000000001"), None);
        for odd in ["", ".", "-", "+", "1e5", "1.2.3", "0x10", "nan", "inf", "١"] {
            assert_eq!(short_decimal(odd.as_bytes()), None, "{odd}");
        }
        assert_eq!(short_decimal(b".5"), Some(0.5));
        assert_eq!(short_decimal(b"5."), Some(5.0));
        assert_eq!(
            short_decimal(b"-0").map(f32::to_bits),
            Some((-0.0f32).to_bits())
        );
    }

    #[test]
    fn reads_the_course_form() {
        let mesh = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        assert_eq!(mesh.positions.len(), 3);
        assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    }

    #[test]
    fn reads_real_world_files() {
        let text = "# exported\r\nmtllib a.mtl\no thing\nv 0 0 0 1\nv 1 0 0\r\nv 1 1 0 0.5 0.5 0.5\nv 0 1 0\n\
                    vn 0 0 1\nvt 0 0\ng side\nusemtl red\ns off\nf 1/1/1 2/2/1 3//1 4 # a quad\nf -4 -3 -1\n";
        let mesh = parse(text).unwrap();
        assert_eq!(mesh.positions[2], Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3], [0, 1, 3]]);
    }

    #[test]
    fn a_file_saved_by_notepad_reads_as_the_same_mesh() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        let notepad = format!("\u{feff}{}", text.replace('\n', "\r\n"));
        let (plain, saved) = (parse(text).unwrap(), parse(&notepad).unwrap());
        assert_eq!(saved.positions, plain.positions);
        assert_eq!(saved.triangles, plain.triangles);
    }

    #[test]
    fn errors_name_line_and_column() {
        assert_eq!(
            parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n").unwrap_err(),
            "m.obj:4:7: expected a vertex index from 1 to 3 (or -3 to -1), found '7'"
        );
        assert_eq!(
            parse("v 0 zero 0\n").unwrap_err(),
            "m.obj:1:5: expected a number, found 'zero'"
        );
        assert_eq!(
            parse("v 0 0\n").unwrap_err(),
            "m.obj:1:6: expected a coordinate, found end of line"
        );
        assert_eq!(
            parse("v 0 0 0\nf 1 1\n").unwrap_err(),
            "m.obj:2:6: expected at least three vertices in a face, found 2 and end of line"
        );
        assert_eq!(
            parse("f 1 2 3\n").unwrap_err(),
            "m.obj:1:3: expected a vertex defined before this face, found '1'"
        );
        assert_eq!(
            parse("\nPK\u{3}\u{4}\n").unwrap_err(),
            "m.obj:2:1: expected an .obj statement (v, f, vn, vt, g, o, s, usemtl, mtllib, or # for a comment), found 'PK\\u{3}\\u{4}'"
        );
        assert_eq!(
            parse("v 0 0 1e39\n").unwrap_err(),
            "m.obj:1:7: expected a number between -1e9 and 1e9, found '1e39'"
        );
        assert_eq!(
            parse("v 0 0 -1.5e9\n").unwrap_err(),
            "m.obj:1:7: expected a number between -1e9 and 1e9, found '-1.5e9'"
        );
        assert_eq!(
            parse("v 0 0 0 nan\n").unwrap_err(),
            "m.obj:1:9: expected a number between -1e9 and 1e9, found 'nan'"
        );
        assert_eq!(
            parse("v 0 0 0 w\n").unwrap_err(),
            "m.obj:1:9: expected a number or end of line, found 'w'"
        );
    }
}
