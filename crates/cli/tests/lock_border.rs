//! `simplify --lock-border`: QEM keeps every border vertex of an open mesh where it was;
//! GNG3D refuses the flag.

mod common;
use common::{gng3d, succeeded};

#[test]
fn lock_border_keeps_the_border_and_gng_refuses_it() {
    let dir = tempfile::tempdir().unwrap();
    let grid = gng3d::mesh::procedural::unit_square_grid(16);
    let input = dir.path().join("grid.ply");
    gng3d::mesh::io::save(&grid.clone().into(), &input).unwrap();
    // Independent: the vertices on the square's sides.
    let border: Vec<glam::Vec3> = grid
        .positions
        .iter()
        .copied()
        .filter(|p| p.x == 0.0 || p.y == 0.0 || p.x == 1.0 || p.y == 1.0)
        .collect();
    assert_eq!(border.len(), 64);
    let kept = |extra: &[&str]| {
        let out = dir.path().join("out.ply");
        let mut args = vec!["simplify", input.to_str().unwrap(), out.to_str().unwrap()];
        args.extend_from_slice(&["--ratio", "0.2"]);
        args.extend_from_slice(extra);
        succeeded(gng3d(&args));
        let output = gng3d::mesh::io::load(&out).unwrap().mesh;
        border
            .iter()
            .filter(|p| output.positions.contains(p))
            .count()
    };
    assert_eq!(kept(&["--lock-border"]), 64);
    assert!(
        kept(&[]) < 32,
        "without the lock the border's straight runs are contracted"
    );

    let o = gng3d(&[
        "simplify",
        input.to_str().unwrap(),
        dir.path().join("g.ply").to_str().unwrap(),
        "--method",
        "gng",
        "--ratio",
        "0.2",
        "--lock-border",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--lock-border applies to QEM only"));
    assert!(!dir.path().join("g.ply").exists());
}
