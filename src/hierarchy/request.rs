//! The hierarchy request (#38): how far to simplify and what to keep, as the command line's
//! `simplify`, `detail` and `refine` flags, Python's `Hierarchy` and `detail` keywords,
//! C++'s `HierarchyOptions` and a recipe's `[hierarchy]` table give it. One function,
//! [`HierarchyRequest::options_over`], applies a recipe's table under a front end's own
//! settings and checks the result, so no front end reads the table its own way (#36: C++
//! read only `target_vertices`).

use serde::{Deserialize, Serialize};

use super::{FeatureVertices, KeepFeatures, SimplifyOptions, VertexTarget};
use crate::error::{Error, Result};
use crate::request::Spelling;

/// A hierarchy build's settings; an unset one takes its default (or, under
/// [`HierarchyRequest::options_over`], the recipe table's value).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct HierarchyRequest {
    /// Stop at this many vertices ("377") or this share of the input's ("1%").
    #[cfg_attr(feature = "cli", arg(long, value_parser = VertexTarget::parse))]
    pub target_vertices: Option<VertexTarget>,
    /// Stop after this many levels.
    #[cfg_attr(feature = "cli", arg(long))]
    pub levels: Option<usize>,
    /// Never remove a vertex whose error exceeds this fraction of the bounding-box diagonal.
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub max_error: Option<f64>,
    /// Feature vertices kept in the base domain (thesis §4.4.1.1) [default: strong].
    #[cfg_attr(feature = "cli", arg(long, value_enum))]
    pub keep_features: Option<KeepFeatures>,
    /// Feature vertices on a feature line: simplified along their line, so it stays a line
    /// of every level (along-lines), or never removed (keep: the thesis' literal rule)
    /// [default: along-lines]. Needs --keep-features (keep_features) corners, strong or all.
    #[cfg_attr(feature = "cli", arg(long, value_enum))]
    pub feature_vertices: Option<FeatureVertices>,
    /// Weight of the removal error in E(v) (eq. 4.1) [default: 0.75].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub removal_weight: Option<f64>,
    /// Weight of the swap error in E(v) (eq. 4.1) [default: 0.25].
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub swap_weight: Option<f64>,
    /// Test each level's new faces for self-intersections (CGAL) and leave out the clusters
    /// that would cut the surface [default: on]. Off (the command line's
    /// --no-intersection-guard): a quarter less build time on large meshes, but a level may
    /// then cut through a thin part.
    #[cfg_attr(
        feature = "cli",
        arg(
            long = "no-intersection-guard",
            num_args = 0,
            default_missing_value = "false",
            help = GUARD_OFF,
            long_help = GUARD_OFF
        )
    )]
    pub intersection_guard: Option<bool>,
    /// Build in K parts along the Morton curve of the faces, in parallel, their borders
    /// fenced, then continue on their joined bases to the target or error bound (#40;
    /// needs one of them, takes no level limit; levels are made afterwards by refinement).
    #[cfg_attr(feature = "cli", arg(long))]
    pub chunks: Option<usize>,
}

/// The command line's `--no-intersection-guard`, which sets `intersection_guard` off.
#[cfg(feature = "cli")]
const GUARD_OFF: &str = "Skip the test of each level's new faces for self-intersections (CGAL): a quarter less build time on large meshes, but a level may then cut through a thin part";

/// A setting and how its source names it (a front end's own, or the recipe's table).
type Given<T> = Option<(T, Spelling)>;

impl HierarchyRequest {
    /// The build options for an input of `vertices` vertices, this request's settings only.
    ///
    /// # Errors
    /// As [`HierarchyRequest::options_over`].
    pub fn options(&self, vertices: usize, record_levels: bool, spelling: Spelling) -> Result<SimplifyOptions> {
        self.options_over(&HierarchyRequest::default(), vertices, record_levels, spelling)
    }

    /// The build options for an input of `vertices` vertices: each setting this request
    /// gives, else the recipe's `[hierarchy]` `table`'s, else the default. A setting this
    /// request gives replaces the table's, which is then not read at all. Each setting used
    /// is checked, a message naming it as its source spells it (`spelling` for this
    /// request's, `[hierarchy] name` for the table's): a vertex target above the input's
    /// count, a negative or non-finite error or weight, `feature_vertices` where no vertex
    /// is a feature (the table's `feature_vertices` gives way to this request's
    /// `keep_features` none instead).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] with the first rule broken.
    pub fn options_over(
        &self,
        table: &HierarchyRequest,
        vertices: usize,
        record_levels: bool,
        spelling: Spelling,
    ) -> Result<SimplifyOptions> {
        // Each setting with the source that gave it: this request's own, else the table's.
        fn pick<T>(own: Option<T>, table: Option<T>, spelling: Spelling) -> Given<T> {
            own.map(|v| (v, spelling)).or(table.map(|v| (v, Spelling::Table("hierarchy"))))
        }
        let target_vertices = match pick(self.target_vertices, table.target_vertices, spelling) {
            Some((target, source)) => Some(target.resolve(vertices, source)?),
            None => None,
        };
        let max_error = pick(self.max_error, table.max_error, spelling);
        let max_error = non_negative(max_error, "max_error", "fraction of the diagonal")?;
        let removal_weight = pick(self.removal_weight, table.removal_weight, spelling);
        let removal_weight = non_negative(removal_weight, "removal_weight", "weight")?;
        let swap_weight = non_negative(pick(self.swap_weight, table.swap_weight, spelling), "swap_weight", "weight")?;
        let keep = pick(self.keep_features, table.keep_features, spelling);
        // The table's feature_vertices gives way where this request keeps no features (it
        // would have nothing to apply to), so that no table locks a front end out of "none".
        let table_lines = table.feature_vertices.filter(|_| self.keep_features != Some(KeepFeatures::None));
        let lines = pick(self.feature_vertices, table_lines, spelling);
        if let (Some((_, lines_source)), Some((KeepFeatures::None, keep_source))) = (lines, keep) {
            return Err(Error::InvalidInput(format!(
                "{} applies only with {} corners, strong or all (with none, no vertex is a feature)",
                lines_source.of("feature_vertices"),
                keep_source.of("keep_features")
            )));
        }
        let chunks = pick(self.chunks, table.chunks, spelling);
        if let Some((k, source)) = chunks {
            if k == 0 {
                return Err(Error::InvalidInput(format!("{}: give 1 part or more", source.with("chunks", k))));
            }
            if target_vertices.is_none() && max_error.is_none() {
                return Err(Error::InvalidInput(format!(
                    "{} needs a vertex target ({}) or an error bound ({}): a partitioned build stops at one",
                    source.with("chunks", k),
                    spelling.of("target_vertices"),
                    spelling.of("max_error")
                )));
            }
            if let Some((levels, levels_source)) = pick(self.levels, table.levels, spelling) {
                return Err(Error::InvalidInput(format!(
                    "{} takes no level limit yet ({})",
                    source.with("chunks", k),
                    levels_source.with("levels", levels)
                )));
            }
        }
        let defaults = SimplifyOptions::default();
        Ok(SimplifyOptions {
            target_vertices,
            levels: self.levels.or(table.levels),
            max_error,
            keep_features: keep.map_or(defaults.keep_features, |(k, _)| k),
            feature_vertices: lines.map_or(defaults.feature_vertices, |(f, _)| f),
            removal_weight: removal_weight.unwrap_or(defaults.removal_weight),
            swap_weight: swap_weight.unwrap_or(defaults.swap_weight),
            record_levels,
            prevent_intersections: self.intersection_guard.or(table.intersection_guard).unwrap_or(true),
            chunks: chunks.map(|(k, _)| k),
            ..defaults
        })
    }
}

/// A number that must be non-negative and finite, refused naming its field as its source
/// spells it.
fn non_negative(given: Given<f64>, field: &str, what: &str) -> Result<Option<f64>> {
    match given {
        Some((value, source)) if !(value >= 0.0 && value.is_finite()) => {
            Err(Error::InvalidInput(format!("{}: must be a non-negative {what}", source.with(field, value))))
        }
        given => Ok(given.map(|(value, _)| value)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> HierarchyRequest {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn own_settings_replace_the_tables_and_the_rest_come_from_it() {
        let t = table(
            "target_vertices = \"50%\"\nlevels = 3\nmax_error = 0.1\nkeep_features = \"all\"\nfeature_vertices = \"keep\"\nremoval_weight = 0.5\nswap_weight = 2.0\nintersection_guard = false\n",
        );
        let own = HierarchyRequest {
            target_vertices: Some(VertexTarget::Vertices(10)),
            swap_weight: Some(1.0),
            ..Default::default()
        };
        let o = own.options_over(&t, 100, false, Spelling::Flag).unwrap();
        assert_eq!(o.target_vertices, Some(10));
        assert_eq!(o.swap_weight, 1.0);
        assert_eq!((o.levels, o.max_error, o.removal_weight), (Some(3), Some(0.1), 0.5));
        assert_eq!((o.keep_features, o.feature_vertices), (KeepFeatures::All, FeatureVertices::Keep));
        assert!(!o.prevent_intersections);
        // Nothing set: the library's defaults.
        let d = HierarchyRequest::default().options(100, false, Spelling::Flag).unwrap();
        assert_eq!(d, SimplifyOptions::default());
    }

    #[test]
    fn a_broken_setting_is_named_as_its_source_spells_it() {
        let t = table("max_error = -1.0\ntarget_vertices = 500\n");
        let err = |r: Result<SimplifyOptions>| r.unwrap_err().to_string();
        let none = HierarchyRequest::default();
        assert!(
            err(none.options_over(&t, 100, false, Spelling::Flag))
                .contains("[hierarchy] target_vertices = 500 is more")
        );
        let own = HierarchyRequest { target_vertices: Some(VertexTarget::Vertices(50)), ..Default::default() };
        assert!(err(own.options_over(&t, 100, false, Spelling::Keyword)).contains("[hierarchy] max_error = -1"));
        // A setting given replaces the table's broken one, which is not read.
        let own = HierarchyRequest { max_error: Some(0.5), ..own };
        assert_eq!(own.options_over(&t, 100, false, Spelling::Keyword).unwrap().max_error, Some(0.5));
        let bad = HierarchyRequest { swap_weight: Some(f64::NAN), ..Default::default() };
        assert!(err(bad.options(100, false, Spelling::Member)).contains("option .swap_weight = NaN"));
        // A table's feature_vertices gives way to a front end's keep_features = none.
        let none = HierarchyRequest { keep_features: Some(KeepFeatures::None), ..Default::default() };
        let o = none.options_over(&table("feature_vertices = \"keep\""), 100, false, Spelling::Flag).unwrap();
        assert_eq!((o.keep_features, o.feature_vertices), (KeepFeatures::None, FeatureVertices::AlongLines));
        let lines = HierarchyRequest { feature_vertices: Some(FeatureVertices::Keep), ..Default::default() };
        let message = err(lines.options_over(&table("keep_features = \"none\""), 100, false, Spelling::Flag));
        assert!(message.contains("--feature-vertices applies only with [hierarchy] keep_features"), "{message}");
    }

    #[test]
    fn the_table_reads_counts_shares_and_names() {
        assert_eq!(table("target_vertices = 377").target_vertices, Some(VertexTarget::Vertices(377)));
        assert_eq!(table("target_vertices = \"377\"").target_vertices, Some(VertexTarget::Vertices(377)));
        assert_eq!(table("target_vertices = \"1%\"").target_vertices, Some(VertexTarget::Percent(1.0)));
        for bad in ["target_vertices = 0", "target_vertices = \"150%\"", "keep_features = \"most\"", "colour = 1"] {
            assert!(toml::from_str::<HierarchyRequest>(bad).is_err(), "{bad}");
        }
        let json = serde_json::to_string(&table("target_vertices = \"2.5%\"\nlevels = 4")).unwrap();
        assert_eq!(
            serde_json::from_str::<HierarchyRequest>(&json).unwrap(),
            table("target_vertices = \"2.5%\"\nlevels = 4")
        );
    }
}
