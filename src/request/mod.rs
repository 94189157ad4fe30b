//! What the library's validated requests share (#38): how a front end spells a field in
//! the messages `check()` gives, and reading a request from named fields with strict keys
//! (Python's keyword arguments and C++'s option structs arrive so, with no argv between).

pub mod parse;

use serde::de::DeserializeOwned;

use crate::error::{Error, Result};

/// How a front end names a request's field in its messages: the command line's flag
/// (`--tile-size`), Python's keyword argument (`tile_size=`), C++'s option member
/// (`option .tile_size`) or a recipe's table key (`[hierarchy] tile_size`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Spelling {
    /// `--name`.
    Flag,
    /// `name=`.
    Keyword,
    /// `option .name`.
    Member,
    /// `[table] name`: a key of a recipe's table.
    Table(&'static str),
}

impl Spelling {
    /// `field` (a struct field's name, with underscores) as this front end writes it.
    pub fn of(self, field: &str) -> String {
        match self {
            Spelling::Flag => format!("--{}", field.replace('_', "-")),
            Spelling::Keyword => format!("{field}="),
            Spelling::Member => format!("option .{field}"),
            Spelling::Table(table) => format!("[{table}] {field}"),
        }
    }

    /// `field` set to `value`, as this front end writes it: `--kind perlin`, `kind=perlin`,
    /// `option .kind = perlin`, `[table] kind = perlin`.
    pub fn with(self, field: &str, value: impl std::fmt::Display) -> String {
        match self {
            Spelling::Flag => format!("{} {value}", self.of(field)),
            Spelling::Keyword => format!("{field}={value}"),
            Spelling::Member | Spelling::Table(_) => format!("{} = {value}", self.of(field)),
        }
    }
}

/// A request read from a JSON object of its fields (absent ones take their defaults; a
/// `null` is absent). An unknown field or a value of the wrong type is an
/// [`Error::InvalidInput`] naming the field as `spelling` writes it, and the fields there are.
///
/// # Errors
/// Not a JSON object, an unknown field, or a field whose value does not fit it.
pub fn from_fields<R: DeserializeOwned + serde::Serialize + Default>(json: &str, spelling: Spelling) -> Result<R> {
    from_field_map(field_map(json)?, spelling, &[], &[])
}

/// The JSON object of a request's fields.
///
/// # Errors
/// Not a JSON object.
pub fn field_map(json: &str) -> Result<serde_json::Map<String, serde_json::Value>> {
    serde_json::from_str(json)
        .map_err(|e| Error::InvalidInput(format!("the options are not a JSON object of fields: {e}")))
}

/// [`from_fields`] over fields already parsed (a reader that takes some apart first), for a
/// request whose default may leave out fields when it is written (a list written only when
/// it is not empty) or whose reader took some apart: `also` names them, so they are known
/// and listed among the options. Fields in `unlisted` (which the caller refuses) are left
/// out of the list an unknown field's message gives.
///
/// # Errors
/// As [`from_fields`].
pub fn from_field_map<R: DeserializeOwned + serde::Serialize + Default>(
    fields: serde_json::Map<String, serde_json::Value>,
    spelling: Spelling,
    also: &[&str],
    unlisted: &[&str],
) -> Result<R> {
    let mut known = match serde_json::to_value(R::default()) {
        Ok(serde_json::Value::Object(known)) => known,
        _ => return Err(Error::Internal("a request does not serialise to an object".into())),
    };
    for name in also {
        known.entry(name.to_string()).or_insert(serde_json::Value::Null);
    }
    let mut given = serde_json::Map::new();
    for (name, value) in fields {
        if !known.contains_key(&name) {
            let mut names: Vec<String> =
                known.keys().filter(|k| !unlisted.contains(&k.as_str())).map(|k| spelling.of(k)).collect();
            names.sort();
            return Err(Error::InvalidInput(format!(
                "{} is not an option here; the options are {}",
                spelling.of(&name),
                names.join(", ")
            )));
        }
        if !value.is_null() {
            // Each field alone first, so that a value of the wrong type names its field.
            let alone = serde_json::Value::Object([(name.clone(), value.clone())].into_iter().collect());
            serde_json::from_value::<R>(alone)
                .map_err(|e| Error::InvalidInput(format!("{}: {}", spelling.of(&name), plain(&e))))?;
            given.insert(name, value);
        }
    }
    serde_json::from_value(serde_json::Value::Object(given))
        .map_err(|e| Error::InvalidInput(format!("the options do not fit together: {}", plain(&e))))
}

/// serde's message without its position in the (internal) JSON text.
fn plain(e: &serde_json::Error) -> String {
    let text = e.to_string();
    text.split(" at line ").next().unwrap_or(&text).to_string()
}

#[cfg(all(test, feature = "cli"))]
mod request_defaults {
    use crate::analysis::AnalysisRequest;
    use crate::hierarchy::{CompareRequest, HierarchyRequest};
    use crate::noise::NoiseRequest;
    use crate::render::RenderRequest;
    use crate::scene::butterflies::ButterflyParams;
    use crate::scene::compose::SceneParams;
    use crate::scene::menger::MengerRequest;
    use crate::scene::smoke::SmokeParams;
    use crate::terrain::{CloudRequest, TerrainRequest};

    /// A request as the command line reads it when none of its flags is given.
    fn without_flags<R: clap::Args + clap::FromArgMatches>() -> R {
        let matches = R::augment_args(clap::Command::new("request")).try_get_matches_from(["request"]).unwrap();
        R::from_arg_matches(&matches).unwrap()
    }

    /// The flags' defaults are the library's: a flag left out means what a Python keyword
    /// or C++ member left out means (#38).
    #[test]
    fn no_flags_give_each_requests_default() {
        assert_eq!(without_flags::<NoiseRequest>(), NoiseRequest::default());
        assert_eq!(without_flags::<HierarchyRequest>(), HierarchyRequest::default());
        assert_eq!(without_flags::<AnalysisRequest>(), AnalysisRequest::default());
        assert_eq!(without_flags::<CloudRequest>(), CloudRequest::default());
        assert_eq!(without_flags::<CompareRequest>(), CompareRequest::default());
        assert_eq!(without_flags::<RenderRequest>(), RenderRequest::default());
        assert_eq!(without_flags::<TerrainRequest>(), TerrainRequest::default());
        assert_eq!(without_flags::<SmokeParams>(), SmokeParams::default());
        assert_eq!(without_flags::<ButterflyParams>(), ButterflyParams::default());
        assert_eq!(without_flags::<SceneParams>(), SceneParams::default());
        assert_eq!(without_flags::<MengerRequest>(), MengerRequest::default());
    }
}
