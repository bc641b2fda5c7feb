//! Scene text to scene description: the lexer finds the words, the parser checks the grammar of
//! the course's scene format (SCENE_FORMAT.md in the course data) and flattens groups and transforms into a list of placed objects.

pub mod description;
mod lexer;
pub mod obj;
mod parser;
pub(crate) mod validate;

pub use description::SceneDescription;
pub(crate) use lexer::column_after;
pub use lexer::{Token, describe};
pub use parser::{
    MAX_MAGNITUDE, MAX_OCTAVES, MAX_TEXTURE_DEPTH, NUMBER_IN_RANGE, parse_camera, parse_scene,
    parse_scene_bytes, read_scene,
};
pub(crate) use parser::{show_number, show_vector};
