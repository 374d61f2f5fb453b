//! The attribute-deviation columns of the tables of `gng3d reproduce` (one mesh, and the survey
//! of a folder): which measures an input with attributes gets, and how a cell reads.

use metrics::AttributeDeviation;

/// An attribute-deviation measure of a table: samples on each output against the original at
/// their closest points (the direction `gng3d compare` reports).
#[derive(Debug, Clone)]
pub struct AttributeColumn {
    /// Name in the CSV headers and the Markdown tables, with its unit.
    pub name: String,
    /// Short name for the terminal (a few characters; [`AttributeColumn::name`] explains it).
    pub short: &'static str,
    /// The attribute it measures (`uv0`, `normals`, `colors`).
    pub attribute: &'static str,
    /// The value, when the output has the attribute.
    pub get: fn(&AttributeDeviation) -> Option<f64>,
    /// Unit appended to the value in a cell ("", " %", "°").
    pub unit: &'static str,
}

impl AttributeColumn {
    /// The cell of one output: the value, "dropped" where the original has the attribute and
    /// the output does not, "-" where the original does not have it.
    pub fn cell(&self, deviation: Option<&AttributeDeviation>) -> String {
        let Some(a) = deviation else {
            return "-".into();
        };
        match (self.get)(a) {
            Some(v) => format!("{v:.2}{}", self.unit),
            None if a.missing.iter().any(|n| n == self.attribute) => "dropped".into(),
            None => "-".into(),
        }
    }
}

/// The attribute-deviation columns of a table whose outputs have the deviations `measured`: UV
/// mean in texels and the share of UV samples off by more than the threshold (inputs with
/// texture coordinates), the mean normal angle (with normals), the mean colour distance (with
/// colours); none when nothing was measured (no input has attributes), so a positions-only
/// table is as before. The texture size and UV threshold in the names are the first
/// deviation's (one run measures all with the same settings).
pub fn attribute_columns_of<'a>(
    measured: impl IntoIterator<Item = &'a AttributeDeviation>,
) -> Vec<AttributeColumn> {
    let measured: Vec<&AttributeDeviation> = measured.into_iter().collect();
    let Some(first) = measured.first() else {
        return Vec::new();
    };
    let had = |name: &str| {
        measured
            .iter()
            .any(|a| a.compared.iter().chain(&a.missing).any(|n| n == name))
    };
    let (size, threshold) = (first.texture_size, first.uv_threshold);
    let mut columns = Vec::new();
    if had("uv0") {
        columns.push(AttributeColumn {
            name: format!("UV deviation mean (texels of {size}²)"),
            short: "UV",
            attribute: "uv0",
            get: |a| a.backward.uv0.map(|u| u.texels.mean),
            unit: "",
        });
        columns.push(AttributeColumn {
            name: format!("UV samples off by > {threshold} UV"),
            short: "UV off",
            attribute: "uv0",
            get: |a| a.backward.uv0.map(|u| 100.0 * u.over_threshold),
            unit: " %",
        });
    }
    if had("normals") {
        columns.push(AttributeColumn {
            name: "attribute normal deviation mean (degrees)".into(),
            short: "normal",
            attribute: "normals",
            get: |a| a.backward.normals.map(|n| n.mean_degrees),
            unit: "°",
        });
    }
    if had("colors") {
        columns.push(AttributeColumn {
            name: "colour deviation mean (linear RGB distance)".into(),
            short: "RGB",
            attribute: "colors",
            get: |a| a.backward.colors.map(|c| c.mean),
            unit: "",
        });
    }
    columns
}
