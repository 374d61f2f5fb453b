//! The image-space error (`metrics::image_error`): real renderings checked against what can be
//! worked out by hand — zero for identical meshes, the checker's contrast for a half-period UV
//! shift, a quad's projected area, silhouettes that shrink with subdivision, texture rows the
//! right way up.

use glam::{Vec2, Vec3};
use gng3d_metrics::{
    AMBIENT, CHECKER_SQUARE, CHECKER_VALUES, ImageError, ImageErrorParams, MetricsError, Surface,
    Texture, VIEWS, image_error, image_error_with_images,
};
use mesh::TriMesh;
use mesh::attributes::Attributes;

/// Half-extents of the test quad, in the z = 0 plane, centred on the origin.
const HX: f32 = 1.0;
const HY: f32 = 0.5;

/// A flat quad facing ±z with UVs (0, 0) to (1, 0.5) plus `shift`.
fn quad(shift: Vec2) -> (TriMesh, Attributes) {
    let mesh = TriMesh::new(
        vec![
            Vec3::new(-HX, -HY, 0.0),
            Vec3::new(HX, -HY, 0.0),
            Vec3::new(HX, HY, 0.0),
            Vec3::new(-HX, HY, 0.0),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    );
    let mut attributes = Attributes::per_vertex(&mesh);
    attributes.uv0 = Some(
        [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 0.5),
            Vec2::new(0.0, 0.5),
        ]
        .iter()
        .map(|&uv| uv + shift)
        .collect(),
    );
    (mesh, attributes)
}

fn view<'a>(r: &'a ImageError, name: &str) -> &'a gng3d_metrics::ImageStats {
    &r.views.iter().find(|v| v.view == name).unwrap().stats
}

#[test]
fn identical_meshes_have_no_error_and_infinite_psnr() {
    let (mesh, attributes) = mesh::procedural::textured_sphere(12, 24);
    let texture = Texture::from_rgb(
        2,
        2,
        vec![
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 1.0, 0.0],
        ],
        false,
        "test",
    )
    .unwrap();
    let params = ImageErrorParams::default();
    for texture in [None, Some(&texture)] {
        let s = Surface::new(&mesh)
            .with_attributes(Some(&attributes))
            .with_texture(texture);
        let r = image_error(&s, &s, &params).unwrap();
        assert_eq!(r.views.len(), VIEWS.len());
        for s in std::iter::once(&r.overall).chain(r.views.iter().map(|v| &v.stats)) {
            assert!(s.pixels > 0, "{s:?}");
            assert_eq!(s.covered_original, s.covered_simplified);
            assert_eq!((s.rmse, s.mean_abs), (0.0, 0.0));
            assert_eq!(s.psnr_db, f64::INFINITY);
            assert_eq!((s.over_threshold, s.coverage_mismatch), (0.0, 0.0));
        }
        // JSON has no infinity: null, read back as infinity.
        let json = serde_json::to_value(&r).unwrap();
        assert!(json["overall"]["psnr_db"].is_null(), "{json}");
        let back: ImageError = serde_json::from_value(json).unwrap();
        assert_eq!(back.overall.psnr_db, f64::INFINITY);
        assert_eq!(back.shading, r.shading);
    }
}

#[test]
fn a_half_period_uv_shift_swaps_every_checker_square() {
    // Shifting u by one square (half the checker's period) turns every light square dark and
    // every dark one light: seen head-on (light = AMBIENT + (1 − AMBIENT) · 1 = 1), every
    // covered pixel differs by the checker's contrast in each channel, and no silhouette moves.
    let (mesh, a) = quad(Vec2::ZERO);
    let (_, b) = quad(Vec2::new(CHECKER_SQUARE, 0.0));
    let r = image_error(
        &Surface::new(&mesh).with_attributes(Some(&a)),
        &Surface::new(&mesh).with_attributes(Some(&b)),
        &ImageErrorParams::default(),
    )
    .unwrap();
    let contrast = f64::from(CHECKER_VALUES[0] - CHECKER_VALUES[1]);
    for name in ["+z", "-z"] {
        let s = view(&r, name);
        assert!(s.pixels > 1000, "{s:?}");
        assert_eq!(s.coverage_mismatch, 0.0);
        // Pixel centres exactly on a square's border may round either way: a few at most.
        assert!((s.rmse - contrast).abs() < 1e-3, "{name}: {s:?}");
        assert!((s.mean_abs - contrast).abs() < 1e-3, "{name}: {s:?}");
        assert!(s.over_threshold > 0.999, "{name}: {s:?}");
        assert!(
            (s.psnr_db - (-20.0 * contrast.log10())).abs() < 0.02,
            "{s:?}"
        );
    }
    // Seen at an angle the contrast is dimmed by the light: |n·l| = 1/√3 on a diagonal.
    let light = f64::from(AMBIENT) + f64::from(1.0 - AMBIENT) / 3f64.sqrt();
    let s = view(&r, "+x+y+z");
    assert!((s.rmse - contrast * light).abs() < 2e-3, "{s:?}");
    // Edge-on, the quad covers nothing.
    for name in ["+x", "-x", "+y", "-y"] {
        assert_eq!(view(&r, name).pixels, 0, "{name}");
    }
    // Shifting by a whole period changes nothing.
    let (_, c) = quad(Vec2::new(2.0 * CHECKER_SQUARE, 0.0));
    let r = image_error(
        &Surface::new(&mesh).with_attributes(Some(&a)),
        &Surface::new(&mesh).with_attributes(Some(&c)),
        &ImageErrorParams::default(),
    )
    .unwrap();
    assert!(r.overall.rmse < 0.01, "{:?}", r.overall);
}

#[test]
fn a_quad_seen_head_on_covers_its_projected_area() {
    for size in [64, 256, 500] {
        let (mesh, _) = quad(Vec2::ZERO);
        let params = ImageErrorParams {
            size,
            ..ImageErrorParams::default()
        };
        let s = Surface::new(&mesh);
        let r = image_error(&s, &s, &params).unwrap();
        // The camera sits where the bounding sphere (radius half the box diagonal) touches the
        // view cone: distance r / sin(fov / 2); a length L at that distance spans
        // L / (distance · tan(fov / 2)) half-images.
        let half = (params.fov_degrees / 2.0).to_radians();
        let radius = f64::from(HX).hypot(f64::from(HY));
        let distance = radius / half.sin();
        let pixels_per_unit = f64::from(size) / 2.0 / (distance * half.tan());
        let (w, h) = (
            2.0 * f64::from(HX) * pixels_per_unit,
            2.0 * f64::from(HY) * pixels_per_unit,
        );
        for name in ["+z", "-z"] {
            let covered = view(&r, name).covered_original as f64;
            assert!(
                (covered - w * h).abs() <= 2.0 * (w + h),
                "{size} px, {name}: {covered} pixels for an area of {}",
                w * h
            );
        }
    }
}

#[test]
fn silhouette_mismatch_shrinks_as_the_sphere_is_subdivided() {
    let fine = mesh::procedural::icosphere(4);
    let params = ImageErrorParams::default();
    let errors: Vec<_> = (1..=3)
        .map(|k| {
            let coarse = mesh::procedural::icosphere(k);
            image_error(&Surface::new(&fine), &Surface::new(&coarse), &params)
                .unwrap()
                .overall
        })
        .collect();
    assert!(errors[0].coverage_mismatch > 0.0, "{errors:?}");
    for pair in errors.windows(2) {
        assert!(
            pair[1].coverage_mismatch < pair[0].coverage_mismatch,
            "{errors:?}"
        );
        assert!(pair[1].rmse < pair[0].rmse, "{errors:?}");
    }
    // Inscribed polyhedra: the coarse sphere covers less.
    assert!(errors[0].covered_simplified < errors[0].covered_original);
    // Lit with face normals the coarse sphere's facets show: more error than with smooth
    // vertex normals, the same silhouette.
    let flat = ImageErrorParams {
        flat_shading: true,
        ..params
    };
    let coarse = mesh::procedural::icosphere(1);
    let faceted = image_error(&Surface::new(&fine), &Surface::new(&coarse), &flat)
        .unwrap()
        .overall;
    assert!(
        faceted.rmse > errors[0].rmse,
        "{faceted:?} vs {:?}",
        errors[0]
    );
    assert_eq!(faceted.coverage_mismatch, errors[0].coverage_mismatch);
}

#[test]
fn texture_rows_are_the_right_way_up() {
    // A 1 × 4 texture, red in its top half, blue in its bottom half. OBJ's v = 0 is the bottom
    // row: the quad's upper half is red. With glTF's convention (v = 0 at the top) it is blue.
    let (red, blue) = ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
    let (mesh, mut a) = quad(Vec2::ZERO);
    a.uv0 = Some(vec![
        Vec2::new(0.0, 0.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(0.0, 1.0),
    ]);
    let params = ImageErrorParams::default();
    let n = params.size as usize;
    for (v_down, upper) in [(false, red), (true, blue)] {
        let texture = Texture::from_rgb(1, 4, vec![red, red, blue, blue], v_down, "t").unwrap();
        let s = Surface::new(&mesh)
            .with_attributes(Some(&a))
            .with_texture(Some(&texture));
        let (r, images) = image_error_with_images(&s, &s, &params, true).unwrap();
        assert_eq!(r.texture.as_deref(), Some("t"));
        let plus_z = images.iter().find(|i| i.view == "+z").unwrap();
        // A quarter of the quad's height above and below the centre of the image (texel rows'
        // centres: no blending).
        assert_eq!(r.overall.rmse, 0.0);
        let quarter = f64::from(HY / 2.0) / f64::from(HX).hypot(f64::from(HY))
            * (params.fov_degrees / 2.0).to_radians().cos()
            * n as f64
            / 2.0;
        let at = |dy: f64| {
            let y = (n as f64 / 2.0 + dy) as usize;
            plus_z.original[y * n + n / 2]
        };
        let lower = if upper == red { blue } else { red };
        for (pixel, want) in [(at(-quarter), upper), (at(quarter), lower)] {
            for k in 0..3 {
                assert!((pixel[k] - want[k]).abs() < 0.02, "{pixel:?} vs {want:?}");
            }
        }
        let png = plus_z.png().unwrap();
        assert_eq!(&png[1..4], b"PNG");
    }
}

#[test]
fn a_materials_texture_loads_with_its_bytes_and_size() {
    // The OBJ atlas's checker.png (64 × 64 RGB) through the one loader: the bytes it gives a
    // GPU upload are the image's own; an unreadable image is an error naming it.
    let assets = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/assets");
    let loaded = mesh::io::load(&assets.join("fandisk_atlas.obj")).unwrap();
    let found = mesh::io::base_color_texture(loaded.materials.as_ref().unwrap()).unwrap();
    let texture = Texture::load(&found).unwrap();
    assert_eq!(texture.size(), [64, 64]);
    assert!(!texture.v_down());
    let png = image::open(assets.join("checker.png")).unwrap().to_rgba8();
    assert_eq!(texture.rgba8(), png.into_raw());
    let missing = mesh::io::BaseColorTexture {
        bytes: Err("gone".into()),
        ..found
    };
    match Texture::load(&missing) {
        Err(e @ MetricsError::Texture { .. }) => assert!(e.to_string().contains("checker.png")),
        other => panic!("{other:?}"),
    }
}

#[test]
fn bad_parameters_and_textures_are_typed_errors() {
    for (p, name) in [
        (
            ImageErrorParams {
                size: 8,
                ..ImageErrorParams::default()
            },
            "size",
        ),
        (
            ImageErrorParams {
                fov_degrees: 0.0,
                ..ImageErrorParams::default()
            },
            "fov_degrees",
        ),
        (
            ImageErrorParams {
                threshold: f64::NAN,
                ..ImageErrorParams::default()
            },
            "threshold",
        ),
    ] {
        match p.validate() {
            Err(MetricsError::Parameter { name: n, .. }) => assert_eq!(n, name),
            other => panic!("{name}: {other:?}"),
        }
    }
    match Texture::decode(b"not an image", "dir/tex.png", false) {
        Err(e @ MetricsError::Texture { .. }) => {
            assert!(e.to_string().contains("dir/tex.png"), "{e}")
        }
        other => panic!("{other:?}"),
    }
    let empty = TriMesh::new(vec![Vec3::ZERO], vec![]);
    let (mesh, _) = quad(Vec2::ZERO);
    assert!(matches!(
        image_error(
            &Surface::new(&empty),
            &Surface::new(&mesh),
            &ImageErrorParams::default()
        ),
        Err(MetricsError::NoTriangles { mesh: "original" })
    ));
}

#[test]
fn the_error_does_not_depend_on_the_thread_count() {
    let (mesh, attributes) = mesh::procedural::textured_sphere(12, 24);
    let coarse = mesh::procedural::icosphere(2);
    let original = Surface::new(&mesh).with_attributes(Some(&attributes));
    let params = ImageErrorParams::default();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut r = pool
            .install(|| image_error(&original, &Surface::new(&coarse), &params))
            .unwrap();
        r.seconds = 0.0;
        r
    };
    let one = run(1);
    assert!(one.overall.rmse > 0.0);
    assert_eq!(one, run(3));
}
