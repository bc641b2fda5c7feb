//! Recursive descent over the course's scene grammar, without recursion where the scene nests:
//! Groups and Transforms are tracked on an explicit stack, so a file nested a million levels deep
//! parses in constant native stack.

use std::path::Path;

use glam::{DMat4, DVec3, Vec3};

use super::description::{
    CameraSpec, LightSpec, MaterialSpec, Pattern, PhongSpec, PlacedObject, Projection,
    SceneDescription, Shape, TextureSpec,
};
use super::lexer::{Lexer, Token, describe, invalid_utf8_span};
use super::validate::{self, Placing};
use crate::error::Span;
use crate::error::{Diagnostic, Error};

type Result<T> = std::result::Result<T, Diagnostic>;

const OBJECT: &str = "an object (Group, Transform, Sphere, Plane, Triangle or TriangleMesh)";
const TEXTURE_OP: &str = "a transformation (Scale, UniformScale, Translate, XRotate, YRotate, \
                          ZRotate, Rotate or Matrix) or '}' (a texture's Transform holds no object)";
const MATERIAL: &str = "Material, PhongMaterial, Checkerboard, Noise, Marble or Wood";

/// The most octaves a Noise, Marble or Wood texture may sum: each doubles the frequency, and
/// past about 50 a double's fraction has no bits left to vary; 30 is beyond any visible detail.
pub const MAX_OCTAVES: u32 = 30;
/// How deep textures may nest (a texture of textures of ...): each level may shade both of its
/// materials, so the work at a point doubles with every level.
pub const MAX_TEXTURE_DEPTH: u32 = 8;

/// The largest magnitude of any number in a scene or mesh file, of any entry of a Transform's
/// matrix or its inverse, and of any coordinate of a shape once placed in the world.
///
/// Geometry is stored and intersected in single precision, whose largest value is 3.4e38, and
/// the intersection tests multiply coordinates: squared distances, the cross product of two
/// triangle edges and its squared length. Within 1e9 on every axis, the largest of these (that
/// squared length, at most (2·√3·1e9)⁴ ≈ 1.44e38) stays finite; a sphere of radius 3e38 was never
/// hit. No scene needs more: the course's stay below 100, and f32 resolves only 64 units at 1e9.
pub const MAX_MAGNITUDE: f64 = 1e9;

/// What a number out of [`MAX_MAGNITUDE`]'s range is refused as.
pub const NUMBER_IN_RANGE: &str = "a number between -1e9 and 1e9";

/// What Windows' Notepad writes before UTF-8 text.
pub const BYTE_ORDER_MARK: char = '\u{feff}';

/// Reads and parses a scene file.
pub fn read_scene(path: &Path) -> std::result::Result<SceneDescription, Error> {
    let bytes = std::fs::read(path).map_err(|source| Error::Read {
        path: path.to_path_buf(),
        source,
    })?;
    Ok(parse_scene_bytes(path, &bytes)?)
}

/// Parses a scene's bytes (read from standard input, say), which must be UTF-8; `path` names
/// the scene in messages and is where meshes are looked for first.
pub fn parse_scene_bytes(path: &Path, bytes: &[u8]) -> Result<SceneDescription> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let span = invalid_utf8_span(bytes, e.valid_up_to());
        let found = format!("byte 0x{:02x}", bytes[e.valid_up_to()]);
        Diagnostic::expected(path, span, "UTF-8 text", &found)
    })?;
    parse_scene(path, text)
}

/// Parses scene text; `path` is only used to name the file in messages and to find meshes later.
/// A byte-order mark at its start (Notepad's UTF-8) is no part of the scene.
pub fn parse_scene(path: &Path, text: &str) -> Result<SceneDescription> {
    let text = text.strip_prefix(BYTE_ORDER_MARK).unwrap_or(text);
    Parser {
        path,
        lexer: Lexer::new(text),
    }
    .scene(true)
}

/// Parses a camera block written alone, in the scene file's syntax (as the preview's page
/// sends the camera it shows): every rule of a scene's camera, without the rest of a scene.
pub fn parse_camera(path: &Path, text: &str) -> Result<CameraSpec> {
    Ok(Parser {
        path,
        lexer: Lexer::new(text),
    }
    .scene(false)?
    .camera)
}

struct Parser<'a> {
    path: &'a Path,
    lexer: Lexer<'a>,
}

/// A Group or Transform whose closing brace is still to come.
enum Open {
    Group { remaining: u32, total: u32 },
    Transform { parent: Option<u32> },
}

/// What the object list accumulates while the parser walks it.
#[derive(Default)]
struct Objects {
    transforms: Vec<DMat4>,
    objects: Vec<PlacedObject>,
    /// The course's single, global "current material": it ignores nesting.
    current_material: Option<u32>,
    /// Checked once the whole file is read, since Materials may come after the Group.
    material_indices: Vec<(u32, Span)>,
}

impl<'a> Parser<'a> {
    /// The scene; `whole` where it must have its objects (a scene file), not where the text is
    /// a camera alone.
    fn scene(mut self, whole: bool) -> Result<SceneDescription> {
        let mut camera = None;
        let mut background = Vec3::splat(0.5);
        let mut ambient = Vec3::ZERO;
        let mut lights = Vec::new();
        let mut materials = Vec::new();
        let mut objects = Objects::default();
        let mut has_group = false;
        while let Some(token) = self.lexer.next_token() {
            match token.text {
                "OrthographicCamera" | "PerspectiveCamera" => camera = Some(self.camera(token)?),
                "Background" => self.background(&mut background, &mut ambient)?,
                "Lights" => lights = self.lights()?,
                "Materials" => materials = self.materials()?,
                "Group" => {
                    // A later Group replaces the scene's objects, but the current material is
                    // the parser's, global, and carries on into it (SCENE_FORMAT.md §7).
                    objects = Objects {
                        current_material: objects.current_material,
                        material_indices: std::mem::take(&mut objects.material_indices),
                        ..Objects::default()
                    };
                    self.objects(token, &mut objects)?;
                    has_group = true;
                }
                _ => {
                    return Err(self.unexpected(
                        token,
                        "a scene block (OrthographicCamera, PerspectiveCamera, Background, \
                         Lights, Materials or Group)",
                    ));
                }
            }
        }
        let end = self.lexer.end();
        let camera = camera.ok_or_else(|| {
            Diagnostic::expected(
                self.path,
                end,
                "a camera (OrthographicCamera or PerspectiveCamera)",
                "end of file",
            )
        })?;
        // A file cut short before its Group would render as a picture of background alone,
        // which looks like a tracer that misses everything.
        if whole && !has_group {
            return Err(Diagnostic::expected(
                self.path,
                end,
                "the scene's Group (its objects; every scene has one, after the camera)",
                "end of file",
            ));
        }
        for &(index, span) in &objects.material_indices {
            if index as usize >= materials.len() {
                return Err(Diagnostic::expected(
                    self.path,
                    span,
                    &validate::material_index_expected(materials.len()),
                    &format!("'{index}'"),
                ));
            }
        }
        if lights.is_empty() {
            ambient = Vec3::ONE;
        }
        Ok(SceneDescription {
            path: self.path.to_path_buf(),
            camera,
            background,
            ambient,
            lights,
            materials,
            transforms: objects.transforms,
            objects: objects.objects,
        })
    }

    fn camera(&mut self, keyword: Token) -> Result<CameraSpec> {
        self.keyword("{")?;
        self.keyword("center")?;
        let center = self.vec3()?;
        self.keyword("direction")?;
        let direction = self.direction()?;
        self.keyword("up")?;
        let up_span = self.peek_span();
        let up = self.vec3()?;
        if !validate::up_is_across(direction, up) {
            return Err(Diagnostic::expected(
                self.path,
                up_span,
                validate::UP,
                &show_vector(up),
            ));
        }
        let projection = if keyword.text == "OrthographicCamera" {
            self.keyword("size")?;
            let (size, token) = self.number_token()?;
            if !validate::is_positive(size as f32) {
                return Err(self.not_positive(token, validate::POSITIVE_SIZE, size));
            }
            Projection::Orthographic { size: size as f32 }
        } else {
            self.keyword("angle")?;
            let (angle, token) = self.number_token()?;
            if !validate::is_field_of_view(angle as f32) {
                return Err(self.unexpected(token, validate::ANGLE));
            }
            Projection::Perspective {
                angle: angle as f32,
            }
        };
        self.keyword("}")?;
        Ok(CameraSpec {
            center,
            direction,
            up,
            projection,
        })
    }

    fn background(&mut self, background: &mut Vec3, ambient: &mut Vec3) -> Result<()> {
        self.keyword("{")?;
        loop {
            let token = self.next("color, ambientLight or '}'")?;
            match token.text {
                "color" => *background = self.vec3()?,
                "ambientLight" => *ambient = self.vec3()?,
                "}" => return Ok(()),
                _ => return Err(self.unexpected(token, "color, ambientLight or '}'")),
            }
        }
    }

    fn lights(&mut self) -> Result<Vec<LightSpec>> {
        self.keyword("{")?;
        let (count, _) = self.count("numLights")?;
        let mut lights = Vec::new();
        for read in 0..count {
            const LIGHT: &str = "DirectionalLight or PointLight";
            let token = self.next(LIGHT)?;
            if token.text == "}" {
                let expected = more(count - read, "light", "numLights", count);
                return Err(self.unexpected(token, &expected));
            }
            let light = match token.text {
                "DirectionalLight" => {
                    self.keyword("{")?;
                    self.keyword("direction")?;
                    let direction = self.direction()?;
                    self.keyword("color")?;
                    let colour = self.vec3()?;
                    self.keyword("}")?;
                    LightSpec::Directional { direction, colour }
                }
                "PointLight" => self.point_light()?,
                _ => return Err(self.unexpected(token, LIGHT)),
            };
            lights.push(light);
        }
        self.end_of_list("numLights", count)?;
        Ok(lights)
    }

    /// `PointLight { position x y z colour r g b [attenuation c l q] }`, in that order.
    fn point_light(&mut self) -> Result<LightSpec> {
        self.keyword("{")?;
        self.keyword("position")?;
        let position = self.vec3()?;
        self.keyword("color")?;
        let colour = self.vec3()?;
        let mut attenuation = [1.0, 0.0, 0.0];
        let token = self.next("attenuation or '}'")?;
        match token.text {
            "}" => {}
            "attenuation" => {
                for term in &mut attenuation {
                    let (value, token) = self.number_token()?;
                    if !validate::is_not_negative(value as f32) {
                        return Err(self.unexpected(token, validate::ATTENUATION_TERM));
                    }
                    *term = value as f32;
                }
                if !validate::attenuation_falls(attenuation) {
                    let (expected, found) = validate::ATTENUATION;
                    return Err(Diagnostic::expected(self.path, token.span, expected, found));
                }
                self.keyword("}")?;
            }
            _ => return Err(self.unexpected(token, "attenuation or '}'")),
        }
        Ok(LightSpec::Point {
            position,
            colour,
            attenuation,
        })
    }

    fn materials(&mut self) -> Result<Vec<MaterialSpec>> {
        self.keyword("{")?;
        let (count, _) = self.count("numMaterials")?;
        let mut materials = Vec::new();
        let mut depths = Vec::new();
        for read in 0..count {
            let token = self.next(MATERIAL)?;
            if token.text == "}" {
                let expected = more(count - read, "material", "numMaterials", count);
                return Err(self.unexpected(token, &expected));
            }
            let (material, depth) = match token.text {
                // Assignment 1's files say PhongMaterial, assignment 2's say Material.
                "Material" | "PhongMaterial" => {
                    self.keyword("{")?;
                    (MaterialSpec::Phong(self.phong_fields()?), 0)
                }
                "Checkerboard" | "Noise" | "Marble" | "Wood" => {
                    let texture = self.texture(token, read)?;
                    let depth = validate::texture_depth(&texture, &depths).map_err(
                        |(expected, found)| {
                            Diagnostic::expected(self.path, token.span, &expected, &found)
                        },
                    )?;
                    (MaterialSpec::Texture(texture), depth)
                }
                _ => return Err(self.unexpected(token, MATERIAL)),
            };
            materials.push(material);
            depths.push(depth);
        }
        self.end_of_list("numMaterials", count)?;
        Ok(materials)
    }

    /// `Checkerboard|Noise|Marble|Wood { [Transform { ops }] materialIndex a materialIndex b
    /// [octaves n [frequency f amplitude a]] }`, in the course's fixed order; `own` is the
    /// texture's own index among the materials.
    fn texture(&mut self, keyword: Token, own: u32) -> Result<TextureSpec> {
        self.keyword("{")?;
        let mut to_texture = DMat4::IDENTITY;
        let mut token = self.next("Transform or materialIndex")?;
        if token.text == "Transform" {
            self.keyword("{")?;
            let (matrix, end) = self.transform_ops(TEXTURE_OP)?;
            if end.text != "}" {
                return Err(self.unexpected(end, TEXTURE_OP));
            }
            validate::transformation(&matrix, Placing::Texture).map_err(|(expected, found)| {
                Diagnostic::expected(self.path, token.span, &expected, &found)
            })?;
            to_texture = matrix;
            token = self.next("materialIndex")?;
            if token.text != "materialIndex" {
                return Err(self.unexpected(token, "materialIndex"));
            }
        } else if token.text != "materialIndex" {
            return Err(self.unexpected(token, "Transform or materialIndex"));
        }
        let first = self.texture_material(own)?;
        self.keyword("materialIndex")?;
        let second = self.texture_material(own)?;
        let pattern = match keyword.text {
            "Checkerboard" => Pattern::Checkerboard,
            "Noise" => Pattern::Noise {
                octaves: self.octaves()?,
            },
            _ => {
                let octaves = self.octaves()?;
                self.keyword("frequency")?;
                let frequency = self.number()?.0;
                self.keyword("amplitude")?;
                let amplitude = self.number()?.0;
                if keyword.text == "Marble" {
                    Pattern::Marble {
                        octaves,
                        frequency,
                        amplitude,
                    }
                } else {
                    Pattern::Wood {
                        octaves,
                        frequency,
                        amplitude,
                    }
                }
            }
        };
        self.keyword("}")?;
        Ok(TextureSpec {
            pattern,
            to_texture,
            materials: [first, second],
        })
    }

    /// A texture's `materialIndex`: one of the materials listed before the texture.
    fn texture_material(&mut self, own: u32) -> Result<u32> {
        let (index, span) = self.whole_number("materialIndex")?;
        if index >= own {
            let expected = validate::texture_material_expected(own as usize);
            let found = if index == own {
                format!("'{index}', the texture itself")
            } else {
                format!("'{index}'")
            };
            return Err(Diagnostic::expected(self.path, span, &expected, &found));
        }
        Ok(index)
    }

    fn octaves(&mut self) -> Result<u32> {
        self.keyword("octaves")?;
        let expected = validate::octaves_expected();
        let token = self.next(&expected)?;
        match token.text.parse::<u32>() {
            Ok(n) if n <= MAX_OCTAVES => Ok(n),
            _ => Err(self.unexpected(token, &expected)),
        }
    }

    /// A material's fields, each optional, in any order (a field given twice: the last counts,
    /// as in the course's parser), up to the closing brace.
    fn phong_fields(&mut self) -> Result<PhongSpec> {
        const FIELD: &str = "diffuseColor, specularColor, exponent, reflectiveColor, \
                             transparentColor, indexOfRefraction or '}'";
        let mut material = PhongSpec::default();
        loop {
            let token = self.next(FIELD)?;
            match token.text {
                "diffuseColor" => material.diffuse = self.vec3()?,
                "specularColor" => material.specular = self.vec3()?,
                "reflectiveColor" => material.reflective = self.vec3()?,
                "transparentColor" => material.transparent = self.vec3()?,
                "exponent" => {
                    let (value, token) = self.number_token()?;
                    if !validate::is_not_negative(value as f32) {
                        return Err(self.unexpected(token, validate::EXPONENT));
                    }
                    material.exponent = value as f32;
                }
                "indexOfRefraction" => {
                    let (value, token) = self.number_token()?;
                    if !validate::is_positive(value as f32) {
                        return Err(self.not_positive(token, validate::POSITIVE_INDEX, value));
                    }
                    material.index_of_refraction = value as f32;
                }
                "}" => return Ok(material),
                _ => return Err(self.unexpected(token, FIELD)),
            }
        }
    }

    /// The scene's root Group and everything inside it; `first` is the word `Group`.
    fn objects(&mut self, first: Token<'a>, out: &mut Objects) -> Result<()> {
        let mut open: Vec<Open> = Vec::new();
        let mut transform: Option<u32> = None;
        let mut next = Some(first);
        loop {
            if let Some(token) = next.take() {
                match token.text {
                    "Group" => {
                        self.keyword("{")?;
                        let (total, _) = self.count("numObjects")?;
                        open.push(Open::Group {
                            remaining: total,
                            total,
                        });
                    }
                    "Transform" => {
                        next = Some(self.open_transform(token, &mut open, &mut transform, out)?);
                        continue;
                    }
                    "Sphere" | "Plane" | "Triangle" | "TriangleMesh" => {
                        let Some(material) = out.current_material else {
                            return Err(
                                self.unexpected(token, "MaterialIndex before the first object")
                            );
                        };
                        let shape = self.shape(token)?;
                        out.objects.push(PlacedObject {
                            shape,
                            material,
                            transform,
                            span: token.span,
                        });
                    }
                    _ => return Err(self.unexpected(token, OBJECT)),
                }
            }
            match self.next_object(&mut open, &mut transform, out)? {
                Some(token) => next = Some(token),
                None => return Ok(()),
            }
        }
    }

    /// A Transform's operations, multiplied with the Transforms around it into a new entry of
    /// the scene's transforms, which the objects inside refer to; returns the object's keyword.
    fn open_transform(
        &mut self,
        keyword: Token,
        open: &mut Vec<Open>,
        transform: &mut Option<u32>,
        out: &mut Objects,
    ) -> Result<Token<'a>> {
        self.keyword("{")?;
        let (local, object) = self.transform_ops(OBJECT)?;
        let world = match *transform {
            Some(parent) => out.transforms[parent as usize] * local,
            None => local,
        };
        validate::transformation(&world, Placing::Object).map_err(|(expected, found)| {
            Diagnostic::expected(self.path, keyword.span, &expected, &found)
        })?;
        open.push(Open::Transform { parent: *transform });
        *transform = Some(out.transforms.len() as u32);
        out.transforms.push(world);
        Ok(object)
    }

    /// The last object is complete: closes what is finished and reads up to the next object's
    /// keyword (taking the MaterialIndex lines on the way); `None` once the root Group closes.
    fn next_object(
        &mut self,
        open: &mut Vec<Open>,
        transform: &mut Option<u32>,
        out: &mut Objects,
    ) -> Result<Option<Token<'a>>> {
        loop {
            match open.last_mut() {
                None => return Ok(None),
                Some(Open::Transform { parent }) => {
                    *transform = *parent;
                    open.pop();
                    self.keyword("}")?;
                }
                Some(Open::Group {
                    remaining: 0,
                    total,
                }) => {
                    let expected = format!("'}}' (the Group's numObjects is {total})");
                    let token = self.next(&expected)?;
                    if token.text != "}" {
                        return Err(self.unexpected(token, &expected));
                    }
                    open.pop();
                }
                Some(Open::Group { remaining, total }) => {
                    let token = loop {
                        let token = self.next(OBJECT)?;
                        if token.text != "MaterialIndex" {
                            break token;
                        }
                        let (index, span) = self.whole_number("MaterialIndex")?;
                        out.current_material = Some(index);
                        out.material_indices.push((index, span));
                    };
                    if token.text == "}" {
                        let expected = more(*remaining, "object", "the Group's numObjects", *total);
                        return Err(self.unexpected(token, &expected));
                    }
                    *remaining -= 1;
                    return Ok(Some(token));
                }
            }
        }
    }

    /// The operations at the head of a Transform, multiplied in the course's order, and the word
    /// after the last of them (`expected` says what may stand there: an object's keyword, or
    /// `}` in a texture's Transform).
    fn transform_ops(&mut self, expected: &str) -> Result<(DMat4, Token<'a>)> {
        let mut matrix = DMat4::IDENTITY;
        loop {
            let token = self.next(expected)?;
            // Each op is applied to the object before those listed above it: M <- M * op.
            let op = match token.text {
                "Scale" => {
                    let span = self.peek_span();
                    let scale = self.dvec3()?;
                    if scale.x * scale.y * scale.z == 0.0 {
                        return Err(self.singular(span));
                    }
                    DMat4::from_scale(scale)
                }
                "UniformScale" => {
                    let (scale, span) = self.number()?;
                    if scale == 0.0 {
                        return Err(self.singular(span));
                    }
                    DMat4::from_scale(DVec3::splat(scale))
                }
                "Translate" => DMat4::from_translation(self.dvec3()?),
                "XRotate" => DMat4::from_rotation_x(self.number()?.0.to_radians()),
                "YRotate" => DMat4::from_rotation_y(self.number()?.0.to_radians()),
                "ZRotate" => DMat4::from_rotation_z(self.number()?.0.to_radians()),
                "Rotate" => {
                    self.keyword("{")?;
                    let span = self.peek_span();
                    let axis = self.dvec3()?;
                    let (degrees, _) = self.number()?;
                    self.keyword("}")?;
                    // The course does not normalise the axis, which turns a non-unit axis into
                    // something that is no rotation; raycast rotates about the axis as written.
                    let unit = axis.normalize_or_zero();
                    if unit == DVec3::ZERO {
                        return Err(Diagnostic::expected(
                            self.path,
                            span,
                            "a rotation axis of non-zero length",
                            &show_vector(axis.as_vec3()),
                        ));
                    }
                    DMat4::from_axis_angle(unit, degrees.to_radians())
                }
                "Matrix" => {
                    self.keyword("{")?;
                    let span = self.peek_span();
                    let mut rows = [0.0; 16];
                    let mut last_row = Vec::with_capacity(4);
                    for (i, value) in rows.iter_mut().enumerate() {
                        let (number, token) = self.number_token()?;
                        *value = number;
                        if i >= 12 {
                            last_row.push(token);
                        }
                    }
                    self.keyword("}")?;
                    if rows[12..] != [0.0, 0.0, 0.0, 1.0] {
                        let written: Vec<&str> = last_row.iter().map(|t| t.text).collect();
                        return Err(Diagnostic::expected(
                            self.path,
                            last_row[0].span,
                            validate::AFFINE,
                            &describe(&written.join(" ")),
                        ));
                    }
                    let file_matrix = DMat4::from_cols_array(&rows).transpose();
                    if file_matrix.determinant() == 0.0 {
                        return Err(self.singular(span));
                    }
                    // The course's parser multiplies Matrix on the left (M <- Mfile * M), unlike
                    // every other op; raycast keeps that order so course scenes render the same.
                    matrix = file_matrix * matrix;
                    continue;
                }
                _ => return Ok((matrix, token)),
            };
            matrix *= op;
        }
    }

    fn shape(&mut self, keyword: Token) -> Result<Shape> {
        self.keyword("{")?;
        let shape = match keyword.text {
            "Sphere" => {
                self.keyword("center")?;
                let center = self.vec3()?;
                self.keyword("radius")?;
                let (radius, token) = self.number_token()?;
                if !validate::is_positive(radius as f32) {
                    return Err(self.not_positive(token, validate::POSITIVE_RADIUS, radius));
                }
                Shape::Sphere {
                    center,
                    radius: radius as f32,
                }
            }
            "Plane" => {
                self.keyword("normal")?;
                let span = self.peek_span();
                let normal = self.vec3()?;
                self.keyword("offset")?;
                let (offset, _) = self.number()?;
                if !validate::has_direction(normal) {
                    return Err(Diagnostic::expected(
                        self.path,
                        span,
                        validate::PLANE_NORMAL,
                        &show_vector(normal),
                    ));
                }
                let length = normal.length();
                // Dividing both sides of P·n = d by |n| keeps the plane where the file put it.
                Shape::Plane {
                    normal: normal / length,
                    offset: (offset / length as f64) as f32,
                }
            }
            "Triangle" => {
                let mut vertices = [Vec3::ZERO; 3];
                for (name, vertex) in ["vertex0", "vertex1", "vertex2"].iter().zip(&mut vertices) {
                    self.keyword(name)?;
                    *vertex = self.vec3()?;
                }
                Shape::Triangle { vertices }
            }
            _ => {
                self.keyword("obj_file")?;
                let file = self.next("the name of an .obj file")?;
                if file.text == "}" {
                    return Err(self.unexpected(file, "the name of an .obj file"));
                }
                Shape::Mesh {
                    file: file.text.to_string(),
                }
            }
        };
        self.keyword("}")?;
        Ok(shape)
    }

    /// The `}` after the last item of a counted list, which says the count when it is missing.
    fn end_of_list(&mut self, name: &str, count: u32) -> Result<()> {
        let expected = format!("'}}' ({name} is {count})");
        let token = self.next(&expected)?;
        if token.text != "}" {
            return Err(self.unexpected(token, &expected));
        }
        Ok(())
    }

    fn next(&mut self, expected: &str) -> Result<Token<'a>> {
        match self.lexer.next_token() {
            Some(token) => Ok(token),
            None => {
                let end = self.lexer.end();
                Err(Diagnostic::expected(
                    self.path,
                    end,
                    expected,
                    "end of file",
                ))
            }
        }
    }

    /// Where the next word starts (or the end of the file), without taking it.
    fn peek_span(&self) -> Span {
        let mut lexer = self.lexer.clone();
        match lexer.next_token() {
            Some(token) => token.span,
            None => lexer.end(),
        }
    }

    fn keyword(&mut self, keyword: &str) -> Result<Token<'a>> {
        let expected = format!("'{keyword}'");
        let token = self.next(&expected)?;
        if token.text == keyword {
            Ok(token)
        } else {
            Err(self.unexpected(token, &expected))
        }
    }

    fn number(&mut self) -> Result<(f64, Span)> {
        let (value, token) = self.number_token()?;
        Ok((value, token.span))
    }

    /// A number and the word it was written as, for messages that quote the file.
    fn number_token(&mut self) -> Result<(f64, Token<'a>)> {
        let token = self.next("a number")?;
        match token.text.parse::<f64>() {
            // NaN fails the comparison too.
            Ok(value) if value.abs() <= MAX_MAGNITUDE => Ok((value, token)),
            Ok(_) => Err(self.unexpected(token, NUMBER_IN_RANGE)),
            Err(_) => Err(self.unexpected(token, "a number")),
        }
    }

    fn vec3(&mut self) -> Result<Vec3> {
        Ok(self.dvec3()?.as_vec3())
    }

    /// Three numbers at full precision, for transformations: their matrices are built in f64.
    fn dvec3(&mut self) -> Result<DVec3> {
        let x = self.number()?.0;
        let y = self.number()?.0;
        let z = self.number()?.0;
        Ok(DVec3::new(x, y, z))
    }

    /// A vector used as a direction: normalised here, refused if it has no length.
    fn direction(&mut self) -> Result<Vec3> {
        let span = self.peek_span();
        let v = self.vec3()?;
        if !validate::has_direction(v) {
            return Err(Diagnostic::expected(
                self.path,
                span,
                validate::DIRECTION,
                &show_vector(v),
            ));
        }
        Ok(v.normalize())
    }

    /// `name <count>`: how many items of a list follow.
    fn count(&mut self, name: &str) -> Result<(u32, Span)> {
        self.keyword(name)?;
        self.whole_number(name)
    }

    fn whole_number(&mut self, what: &str) -> Result<(u32, Span)> {
        let expected = format!("a whole number from 0 to {} for {what}", u32::MAX);
        let token = self.next(&expected)?;
        match token.text.parse::<u32>() {
            Ok(value) => Ok((value, token.span)),
            Err(_) => Err(self.unexpected(token, &expected)),
        }
    }

    fn unexpected(&self, token: Token, expected: &str) -> Diagnostic {
        let mut found = describe(token.text);
        if token.text.len() > 1 && (token.text.contains('{') || token.text.contains('}')) {
            found.push_str(" (braces must stand apart, with spaces around them)");
        }
        Diagnostic::expected(self.path, token.span, expected, &found)
    }

    /// A size or radius that is not above zero, or is so small that single precision, in which
    /// it is stored, rounds it to zero (a sphere of radius 1e-46 would be no sphere at all).
    fn not_positive(&self, token: Token, expected: &str, value: f64) -> Diagnostic {
        let mut found = describe(token.text);
        if value > 0.0 {
            found.push_str(" (so small that single precision rounds it to zero)");
        }
        Diagnostic::expected(self.path, token.span, expected, &found)
    }

    fn singular(&self, span: Span) -> Diagnostic {
        let (expected, found) = validate::singular();
        Diagnostic::expected(self.path, span, &expected, &found)
    }
}

/// What a `}` that comes too early should have been: "2 more objects (numObjects is 3)".
fn more(missing: u32, item: &str, count_name: &str, count: u32) -> String {
    let plural = if missing == 1 { "" } else { "s" };
    format!("{missing} more {item}{plural} ({count_name} is {count})")
}

/// A computed value beyond [`MAX_MAGNITUDE`] for a message, to six digits (`1e10`, not
/// `1.0000000000000002e10` or the f32 `1e-5`'s `1.000000025e10`), or more where six would round
/// it down to the bound itself.
pub(crate) fn show_number(x: f64) -> String {
    let round = |digits: usize| -> f64 { format!("{x:.digits$e}").parse().unwrap_or(x) };
    let mut rounded = round(5);
    if rounded.abs() <= MAX_MAGNITUDE {
        rounded = round(15);
    }
    format!("{rounded:e}")
}

/// A vector as the file could have written it: its values are single precision, shown in the
/// shortest form that reads back the same, with an exponent where plain digits would run long.
pub(crate) fn show_vector(v: Vec3) -> String {
    let show = |x: f32| {
        if x == 0.0 || (1e-4..1e16).contains(&x.abs()) {
            format!("{x}")
        } else {
            format!("{x:e}")
        }
    };
    format!("'{} {} {}'", show(v.x), show(v.y), show(v.z))
}
