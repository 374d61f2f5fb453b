//! The MTL reader: the statements of each `newmtl` that convert to glTF ([`parse_mtl`]).

use std::collections::BTreeSet;

/// The statements of one `newmtl` that are converted to glTF.
#[derive(Debug, Default, Clone, PartialEq)]
pub(crate) struct MtlMaterial {
    /// The `newmtl` name.
    pub name: String,
    /// `Kd` (diffuse colour).
    pub kd: Option<[f32; 3]>,
    /// Opacity: `d`, or `1 − Tr` when there is no `d`.
    pub opacity: Option<f32>,
    /// `Tr` seen (used when there is no `d`).
    tr: Option<f32>,
    /// `Ns` (specular exponent).
    pub ns: Option<f32>,
    /// `Pr` (roughness, PBR extension of MTL).
    pub pr: Option<f32>,
    /// `Pm` (metallic, PBR extension of MTL).
    pub pm: Option<f32>,
    /// `Ke` (emissive colour).
    pub ke: Option<[f32; 3]>,
    /// `map_Kd` file name (options removed), as written.
    pub map_kd: Option<String>,
}

/// The `map_*` options and how many values each takes (`-o`, `-s`, `-t` take one to three).
const MAP_OPTIONS: &[(&str, usize)] = &[
    ("-blendu", 1),
    ("-blendv", 1),
    ("-bm", 1),
    ("-boost", 1),
    ("-cc", 1),
    ("-clamp", 1),
    ("-imfchan", 1),
    ("-mm", 2),
    ("-o", 3),
    ("-s", 3),
    ("-t", 3),
    ("-texres", 1),
    ("-type", 1),
];

/// Parses material library text: the materials with their converted statements, and the
/// statements not converted (their keywords as written, `map_Kd` options as `map_Kd -s`;
/// values that do not parse as `Kd (unreadable)` and so on).
pub(crate) fn parse_mtl(text: &[u8]) -> (Vec<MtlMaterial>, BTreeSet<String>) {
    let text = String::from_utf8_lossy(text);
    let mut materials: Vec<MtlMaterial> = Vec::new();
    let mut dropped = BTreeSet::new();
    for line in text.lines() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let (keyword, rest) = line
            .split_once(|c: char| c.is_ascii_whitespace())
            .map_or((line, ""), |(k, r)| (k, r.trim()));
        let lower = keyword.to_ascii_lowercase();
        if lower == "newmtl" {
            materials.push(MtlMaterial {
                name: rest.to_string(),
                ..MtlMaterial::default()
            });
            continue;
        }
        let Some(m) = materials.last_mut() else {
            dropped.insert(format!("{keyword} (before any newmtl)"));
            continue;
        };
        let floats = |n: usize| -> Option<Vec<f32>> {
            let v: Option<Vec<f32>> = rest
                .split_ascii_whitespace()
                .map(|t| t.parse().ok())
                .collect();
            v.filter(|v| v.len() == n || (n == 3 && v.len() == 1))
                .map(|v| {
                    if v.len() == 1 && n == 3 {
                        vec![v[0]; 3]
                    } else {
                        v
                    }
                })
        };
        let mut unreadable = || {
            dropped.insert(format!("{keyword} (unreadable values)"));
        };
        match lower.as_str() {
            "kd" | "ke" => match floats(3) {
                Some(v) if lower == "kd" => m.kd = Some([v[0], v[1], v[2]]),
                Some(v) => m.ke = Some([v[0], v[1], v[2]]),
                None => unreadable(),
            },
            "d" | "tr" | "ns" | "pr" | "pm" => match floats(1) {
                Some(v) => {
                    let x = v[0];
                    match lower.as_str() {
                        "d" => m.opacity = Some(x),
                        "tr" => m.tr = Some(x),
                        "ns" => m.ns = Some(x),
                        "pr" => m.pr = Some(x),
                        _ => m.pm = Some(x),
                    }
                }
                None => unreadable(),
            },
            "map_kd" => {
                let words: Vec<&str> = rest.split_ascii_whitespace().collect();
                let mut i = 0;
                while i < words.len() && words[i].starts_with('-') {
                    let option = words[i];
                    dropped.insert(format!("{keyword} option {option}"));
                    i += 1;
                    let takes = MAP_OPTIONS
                        .iter()
                        .find(|(o, _)| o.eq_ignore_ascii_case(option))
                        .map_or(0, |&(_, n)| n);
                    let numeric = matches!(option, "-o" | "-s" | "-t");
                    for _ in 0..takes {
                        if i >= words.len() - 1 || (numeric && words[i].parse::<f32>().is_err()) {
                            break;
                        }
                        i += 1;
                    }
                }
                let file = words[i.min(words.len())..].join(" ");
                if file.is_empty() {
                    dropped.insert(format!("{keyword} (no file)"));
                } else {
                    m.map_kd = Some(file);
                }
            }
            _ => {
                dropped.insert(keyword.to_string());
            }
        }
    }
    for m in &mut materials {
        if m.opacity.is_none() {
            m.opacity = m.tr.map(|t| 1.0 - t);
        }
    }
    (materials, dropped)
}
