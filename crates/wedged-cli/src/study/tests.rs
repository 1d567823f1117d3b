//! The tests of `study.rs`.

use super::*;

fn table(text: &str) -> Table {
    text.parse().unwrap()
}

/// `refine` divides a Gmsh script's `size_factor` (1 where it has none); a mesh file has none.
#[test]
fn a_scripts_mesh_sizes_scale() {
    let script = table("mu = 2.0\n[mesh]\ngmsh = \"body.GEO\"\n[mesh.parameters]\nlc = 0.1\n");
    let factor = |t: &Table| t["mesh"]["size_factor"].as_float();
    let coarse = table("[mesh]\ngmsh = \"body.geo\"\nsize_factor = 2.0\n");
    let refine = Parameter {
        key: REFINE.into(),
        values: vec![1.5],
    };
    let finer = apply(&coarse, std::slice::from_ref(&refine), &[4.0]).unwrap();
    assert_eq!(factor(&finer), Some(0.5));
    assert_eq!(
        factor(&apply(&script, std::slice::from_ref(&refine), &[1.5]).unwrap()),
        Some(1.0 / 1.5)
    );
    let e = apply(&script, std::slice::from_ref(&refine), &[0.5]).unwrap_err();
    assert!(e.contains("refinement factor is a number >= 1"), "{e}");
    let words = table("[mesh]\ngmsh = \"body.geo\"\nsize_factor = \"two\"\n");
    let e = apply(&words, std::slice::from_ref(&refine), &[2.0]).unwrap_err();
    assert!(e.contains("size_factor is not a number"), "{e}");
    let e = apply(&table("[mesh]\ngmsh = \"body.msh\"\n"), &[refine], &[2.0]).unwrap_err();
    assert!(e.contains("applies to a generated body"), "{e}");
    assert!(refines("mesh.size_factor") && refines(REFINE));
    assert!(!refines("mesh.parameters.lc"));
}

#[test]
fn vary_lists_and_ranges() {
    let p = parse_vary("material.poisson=0.1, 0.2,0.3").unwrap();
    assert_eq!(p.key, "material.poisson");
    assert_eq!(p.values, vec![0.1, 0.2, 0.3]);
    let p = parse_vary("half_angle=10:30:5").unwrap();
    assert_eq!(p.values, vec![10.0, 15.0, 20.0, 25.0, 30.0]);
    let p = parse_vary("x=0:1:3").unwrap();
    assert_eq!(p.values, vec![0.0, 0.5, 1.0]);
    for bad in [
        "poisson",
        "=1",
        "a..b=1",
        "a=1,x",
        "a=1:2",
        "a=1:2:0",
        "a=1:2:1",
        "a=1,1",
        "a=nan",
        "a=0:1:100000",
    ] {
        assert!(parse_vary(bad).is_err(), "{bad} was accepted");
    }
}

#[test]
fn the_grid_is_the_product_first_key_slowest() {
    let a = parse_vary("a=1,2").unwrap();
    let b = parse_vary("b=10,20,30").unwrap();
    let grid = points(&[a.clone(), b]).unwrap();
    assert_eq!(grid.len(), 6);
    assert_eq!(grid[0], vec![1.0, 10.0]);
    assert_eq!(grid[1], vec![1.0, 20.0]);
    assert_eq!(grid[5], vec![2.0, 30.0]);
    assert!(points(&[a.clone(), a]).is_err());
    assert_eq!(points(&[]).unwrap(), vec![Vec::<f64>::new()]);
}

#[test]
fn points_apply_to_keys_the_file_has() {
    let base = table(
        "mu = 2.0\n[mesh.generate]\nkind = \"plug2d\"\nbottom_width = 1.0\ntop_width = 2.0\n\
         height = 1.0\nnx = 8\nny = 6\n[material]\nyoung = 1.0\npoisson = 0.3\n",
    );
    let params = [
        parse_vary("material.poisson=0.25").unwrap(),
        parse_vary("refine=2").unwrap(),
        parse_vary("half_angle=45").unwrap(),
    ];
    let t = apply(&base, &params, &[0.25, 2.0, 45.0]).unwrap();
    assert_eq!(t["material"]["poisson"].as_float(), Some(0.25));
    let g = &t["mesh"]["generate"];
    assert_eq!(g["nx"].as_integer(), Some(16));
    assert_eq!(g["ny"].as_integer(), Some(12));
    assert!((g["top_width"].as_float().unwrap() - 3.0).abs() < 1e-12);
    // An integer key takes whole numbers only; a missing key is an error, not a no-op.
    let ny = [parse_vary("mesh.generate.ny=2.5").unwrap()];
    assert!(apply(&base, &ny, &[2.5])
        .unwrap_err()
        .contains("whole number"));
    let ny = [parse_vary("mesh.generate.ny=12").unwrap()];
    assert_eq!(
        apply(&base, &ny, &[12.0]).unwrap()["mesh"]["generate"]["ny"].as_integer(),
        Some(12)
    );
    let typo = [parse_vary("material.poison=0.2").unwrap()];
    assert!(apply(&base, &typo, &[0.2])
        .unwrap_err()
        .contains("no such key"));
    let kind = [parse_vary("mesh.generate.kind=1").unwrap()];
    assert!(apply(&base, &kind, &[1.0])
        .unwrap_err()
        .contains("not a number"));
    let stiffness = table("mu = 1.0\n[stiffness]\nrows = [[1.0]]\n");
    let r = [parse_vary("refine=2").unwrap()];
    assert!(apply(&stiffness, &r, &[2.0])
        .unwrap_err()
        .contains("generated body"));
    let r = [parse_vary("refine=1.5").unwrap()];
    assert!(apply(&base, &r, &[1.5]).is_err());
    let a = [parse_vary("half_angle=95").unwrap()];
    assert!(apply(&base, &a, &[95.0]).is_err());
    // The base is not changed.
    assert_eq!(base["material"]["poisson"].as_float(), Some(0.3));
}

#[test]
fn the_csv_reads_back_as_written() {
    let params = [
        parse_vary("material.poisson=0.1,0.2").unwrap(),
        parse_vary("refine=1").unwrap(),
    ];
    let rows = vec![
        Row {
            values: vec!["0.1".into(), "1".into()],
            m: 16,
            h: Some(0.2),
            status: "wedged".into(),
            mu_star: Some(1.7882431241639898),
            lower: Some(1.7882431223),
            upper: Some(1.7882431241639898),
            complete: true,
            seconds: 0.021,
        },
        Row {
            values: vec!["0.2".into(), "1".into()],
            m: 16,
            h: None,
            status: "incomplete".into(),
            mu_star: None,
            lower: None,
            upper: Some(2.5),
            complete: false,
            seconds: 3.0,
        },
    ];
    let text = csv(&params, &rows);
    let back = read_csv(&text, &params).unwrap();
    assert_eq!(back.len(), 2);
    assert_eq!(back[&rows[0].values], rows[0]);
    assert_eq!(back[&rows[1].values], rows[1]);
    // Another study's file is refused, and a damaged line is named.
    let other = [parse_vary("material.young=1").unwrap()];
    assert!(read_csv(&text, &other).unwrap_err().contains("header"));
    let damaged = text.replace("wedged,1.78", "wedged,x1.78");
    assert!(read_csv(&damaged, &params)
        .unwrap_err()
        .starts_with("line 2"));
    assert!(read_csv("", &params).unwrap().is_empty());
}

#[test]
fn extrapolation_recovers_a_known_limit_and_order() {
    for (limit, c, p) in [(1.8, 0.3, 1.0), (1.8, -0.7, 2.0), (0.5, 2.0, 1.5)] {
        // Uneven refinement, listed in any order.
        let series: Vec<(f64, f64)> = [0.05, 0.4, 0.1, 0.2, 0.07]
            .iter()
            .map(|&h: &f64| (h, limit + c * h.powf(p)))
            .collect();
        let e = extrapolate(&series).unwrap();
        assert!((e.limit - limit).abs() < 1e-9, "{e:?}");
        assert!((e.order - p).abs() < 1e-6, "{e:?}");
        assert!((e.coefficient - c).abs() < 1e-6, "{e:?}");
    }
    // An order below `MIN_ORDER` is not extrapolated (its limit lies far beyond the
    // data); just above it, it is.
    for (p, found) in [(0.057, false), (0.3, false), (0.6, true)] {
        let series: Vec<(f64, f64)> = [0.031, 0.0265, 0.0232]
            .iter()
            .map(|&h: &f64| (h, 2.087 - 0.6 * h.powf(p)))
            .collect();
        let e = extrapolate(&series);
        assert_eq!(e.is_some(), found, "p = {p}: {e:?}");
        if let Some(e) = e {
            assert!((e.limit - 2.087).abs() < 1e-9 && (e.order - p).abs() < 1e-6);
        }
    }
    // Logarithmic growth is not a power law; it is recognised as what it is.
    let log: Vec<(f64, f64)> = [0.2, 0.1, 0.07, 0.05]
        .iter()
        .map(|&h: &f64| (h, 1.8 - 0.0165 * h.ln()))
        .collect();
    assert!(extrapolate(&log).is_none());
    let g = logarithmic(&log).unwrap();
    assert!((g.slope - 0.0165).abs() < 1e-12 && g.spread < 1e-9, "{g:?}");
    let power: Vec<(f64, f64)> = [0.2, 0.1, 0.05]
        .iter()
        .map(|&h: &f64| (h, 1.8 + 0.3 * h))
        .collect();
    assert!(
        logarithmic(&power).is_none(),
        "halving steps are not logarithmic"
    );
    // Not monotone, too few points: no claim.
    assert!(extrapolate(&[(0.4, 1.0), (0.2, 2.0), (0.1, 1.5)]).is_none());
    assert!(extrapolate(&[(0.4, 1.0), (0.2, 2.0)]).is_none());
    assert!(extrapolate(&[(0.4, 1.0), (0.4, 2.0), (0.2, 1.5)]).is_none());
}
