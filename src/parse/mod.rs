//! Scene text to scene description: the lexer finds the words, the parser checks the grammar of
//! the course's scene format (SCENE_FORMAT.md in the course data) and flattens groups and transforms into a list of placed objects.

mod lexer;
mod parser;

pub(crate) use lexer::column_after;
pub use lexer::{Span, Token, describe};
pub use parser::{
    MAX_MAGNITUDE, MAX_OCTAVES, MAX_TEXTURE_DEPTH, NUMBER_IN_RANGE, parse_scene, parse_scene_bytes,
    read_scene,
};
pub(crate) use parser::{show_number, show_vector};
