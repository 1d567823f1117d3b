//! Tests of `svg.rs`.

use super::geometry::{add3, norm3};
use super::legend::STATUSES;
use super::*;
use crate::report::sig4;
use wedged::fe::boundary::{Boundary, Frame};
use wedged::fe::{Configuration, Element, ElementKind, Mesh};

/// A minimal XML well-formedness check: balanced, properly nested tags, quoted attributes,
/// no stray `<` or `&` in text.
fn check_xml(s: &str) -> Result<(), String> {
    let mut stack: Vec<String> = Vec::new();
    let mut rest = s;
    let mut roots = 0;
    let check_text = |t: &str| -> Result<(), String> {
        let mut t = t;
        while let Some(i) = t.find('&') {
            let after = &t[i + 1..];
            let end = after.find(';').ok_or("unterminated entity")?;
            let name = &after[..end];
            let ok = ["amp", "lt", "gt", "quot", "apos"].contains(&name)
                || (name.starts_with('#') && name.len() > 1);
            if !ok {
                return Err(format!("bad entity &{name};"));
            }
            t = &after[end + 1..];
        }
        Ok(())
    };
    while let Some(i) = rest.find('<') {
        check_text(&rest[..i])?;
        if !stack.is_empty() || rest[..i].trim().is_empty() {
        } else {
            return Err("text outside the root element".into());
        }
        rest = &rest[i..];
        if let Some(r) = rest.strip_prefix("<!--") {
            let end = r.find("-->").ok_or("unterminated comment")?;
            rest = &r[end + 3..];
            continue;
        }
        if let Some(r) = rest.strip_prefix("<?") {
            let end = r.find("?>").ok_or("unterminated declaration")?;
            rest = &r[end + 2..];
            continue;
        }
        let end = rest.find('>').ok_or("unterminated tag")?;
        let tag = &rest[1..end];
        rest = &rest[end + 1..];
        if tag.contains('<') {
            return Err(format!("'<' inside tag {tag}"));
        }
        if let Some(name) = tag.strip_prefix('/') {
            let open = stack.pop().ok_or(format!("unexpected </{name}>"))?;
            if open != name.trim() {
                return Err(format!("<{open}> closed by </{name}>"));
            }
            continue;
        }
        let self_closing = tag.ends_with('/');
        let body = tag.trim_end_matches('/');
        let name = body
            .split_whitespace()
            .next()
            .ok_or("empty tag")?
            .to_string();
        // Attributes: name="value" pairs.
        let mut attrs = body[name.len()..].trim();
        while !attrs.is_empty() {
            let eq = attrs
                .find('=')
                .ok_or(format!("attribute without value in <{tag}>"))?;
            let value = attrs[eq + 1..].trim_start();
            let quote = value.chars().next().ok_or("missing value")?;
            if quote != '"' && quote != '\'' {
                return Err(format!("unquoted attribute in <{tag}>"));
            }
            let close = value[1..].find(quote).ok_or("unterminated attribute")?;
            check_text(&value[1..1 + close])?;
            attrs = value[close + 2..].trim_start();
        }
        if stack.is_empty() {
            roots += 1;
        }
        if !self_closing {
            stack.push(name);
        }
    }
    check_text(rest)?;
    if !rest.trim().is_empty() {
        return Err("text after the root element".into());
    }
    if let Some(open) = stack.pop() {
        return Err(format!("<{open}> not closed"));
    }
    if roots != 1 {
        return Err(format!("{roots} root elements"));
    }
    Ok(())
}

fn count(s: &str, pattern: &str) -> usize {
    s.matches(pattern).count()
}

fn boundary(
    contact_nodes: Vec<usize>,
    frames: Vec<Frame>,
    contact_facets: Vec<Vec<usize>>,
    clamped: Vec<usize>,
) -> Boundary {
    Boundary {
        contact_nodes,
        frames,
        contact_facets,
        clamped,
        rollers: vec![],
        clamped_contact: 0,
    }
}

fn frame_2d(n: P3) -> Frame {
    Frame {
        n,
        t1: [-n[1], n[0], 0.0],
        t2: [0.0; 3],
    }
}

/// The 2D sample: a trapezoidal plug (bottom width 1, top width 2, height 1, 6 x 4 quads)
/// wedged between two slanted walls, clamped on top, pulled down and squeezed inwards.
struct Sample {
    mesh: Mesh,
    boundary: Boundary,
    status: Vec<NodeStatus>,
    state: Configuration,
    rays: Vec<Configuration>,
}

fn plug_2d() -> Sample {
    let (nx, ny) = (6, 4);
    let node = |i: usize, j: usize| j * (nx + 1) + i;
    let half_width = |y: f64| 0.5 + 0.5 * y;
    let mut coords = Vec::new();
    for j in 0..=ny {
        let y = j as f64 / ny as f64;
        let w = half_width(y);
        for i in 0..=nx {
            coords.push([-w + 2.0 * w * i as f64 / nx as f64, y, 0.0]);
        }
    }
    let mut elements = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            elements.push(Element {
                kind: ElementKind::Quad4,
                nodes: vec![
                    node(i, j),
                    node(i + 1, j),
                    node(i + 1, j + 1),
                    node(i, j + 1),
                ],
            });
        }
    }
    let mesh = Mesh::new(2, coords.clone(), elements, vec![]).unwrap();
    let s = 1.25f64.sqrt();
    let left_n = [1.0 / s, 0.5 / s, 0.0];
    let right_n = [-1.0 / s, 0.5 / s, 0.0];
    let mut contact_nodes = Vec::new();
    let mut frames = Vec::new();
    for j in 0..ny {
        contact_nodes.push(node(0, j));
        frames.push(frame_2d(left_n));
    }
    for j in 0..ny {
        contact_nodes.push(node(nx, j));
        frames.push(frame_2d(right_n));
    }
    let mut facets = Vec::new();
    for j in 0..ny {
        facets.push(vec![node(0, j + 1), node(0, j)]);
        facets.push(vec![node(nx, j), node(nx, j + 1)]);
    }
    let clamped = (0..=nx).map(|i| node(i, ny)).collect();
    let boundary = boundary(contact_nodes, frames, facets, clamped);
    use NodeStatus::*;
    let status = vec![
        Separated, SlipMinus, Stick, Stick, Grazing, SlipPlus, Stick, Stick,
    ];

    // Pulled down, squeezed inwards along the walls (u . n = 0 there), the centre sagging.
    let displacement: Vec<P3> = coords
        .iter()
        .map(|x| {
            let w = half_width(x[1]);
            let s = 1.0 - x[1];
            let r = x[0] / w;
            [-0.0125 * s * r, -0.025 * s - 0.03 * s * (1.0 - r * r), 0.0]
        })
        .collect();
    let mut displacement = displacement;
    // The separated bottom-left corner lifts off the wall.
    displacement[node(0, 0)][0] += 0.01;
    let mut force = vec![[0.0; 3]; coords.len()];
    let pressed: [(usize, f64, f64); 6] = [
        // (contact index, r_n, r_t upwards along the wall)
        (1, 0.14, 0.112),
        (2, 0.17, 0.09),
        (3, 0.19, 0.08),
        (5, 0.15, 0.12),
        (6, 0.17, 0.1),
        (7, 0.18, 0.07),
    ];
    for (i, rn, rt) in pressed {
        let a = boundary.contact_nodes[i];
        let n = boundary.frames[i].n;
        let up = [-n[1] * n[0].signum(), n[0].abs(), 0.0];
        force[a] = [rn * n[0] + rt * up[0], rn * n[1] + rt * up[1], 0.0];
    }
    let von_mises = mesh
        .elements()
        .iter()
        .map(|e| {
            let c = e.nodes.iter().fold([0.0; 2], |s, &a| {
                [s[0] + 0.25 * coords[a][0], s[1] + 0.25 * coords[a][1]]
            });
            let r = c[0].abs() / half_width(c[1]);
            0.2 + 0.9 * r * r * (1.0 - 0.5 * c[1]) + 0.3 * (1.0 - c[1])
        })
        .collect::<Vec<_>>();
    let stress = von_mises
        .iter()
        .map(|&v| [-0.6 * v, -0.2 * v, -0.24 * v, 0.0, 0.0, 0.1 * v])
        .collect();
    let state = Configuration {
        displacement,
        force,
        stress,
        von_mises,
    };
    let rays = vec![state.clone()];
    Sample {
        mesh,
        boundary,
        status,
        state,
        rays,
    }
}

/// The 3D sample: a square frustum (bottom side 1, top side 2, height 1, 4 x 4 x 2 hexes)
/// in a pyramidal hole, clamped on top.
fn plug_3d() -> Sample {
    let (n, nz) = (4usize, 2usize);
    let node = |i: usize, j: usize, k: usize| (k * (n + 1) + j) * (n + 1) + i;
    let half = |z: f64| 0.5 + 0.5 * z;
    let mut coords = Vec::new();
    for k in 0..=nz {
        let z = k as f64 / nz as f64;
        let w = half(z);
        for j in 0..=n {
            for i in 0..=n {
                coords.push([
                    -w + 2.0 * w * i as f64 / n as f64,
                    -w + 2.0 * w * j as f64 / n as f64,
                    z,
                ]);
            }
        }
    }
    let mut elements = Vec::new();
    for k in 0..nz {
        for j in 0..n {
            for i in 0..n {
                let bottom = [
                    node(i, j, k),
                    node(i + 1, j, k),
                    node(i + 1, j + 1, k),
                    node(i, j + 1, k),
                ];
                let mut nodes = bottom.to_vec();
                nodes.extend(bottom.iter().map(|&a| a + (n + 1) * (n + 1)));
                elements.push(Element {
                    kind: ElementKind::Hex8,
                    nodes,
                });
            }
        }
    }
    let mesh = Mesh::new(3, coords.clone(), elements, vec![]).unwrap();
    let side = |a: usize| {
        let i = a % (n + 1);
        let j = (a / (n + 1)) % (n + 1);
        i == 0 || i == n || j == 0 || j == n
    };
    let mut contact_nodes = Vec::new();
    let mut frames = Vec::new();
    let mut status = Vec::new();
    let mut force = vec![[0.0; 3]; coords.len()];
    let mut displacement = vec![[0.0; 3]; coords.len()];
    for (a, x) in coords.iter().enumerate() {
        let w = half(x[2]);
        let s = 1.0 - x[2];
        displacement[a] = [-0.02 * s * x[0] / w, -0.02 * s * x[1] / w, -0.05 * s];
        if x[2] < 1.0 && side(a) {
            let mut nn: P3 = [0.0, 0.0, 0.0];
            if (x[0] + w).abs() < 1e-9 {
                nn[0] += 1.0;
            }
            if (x[0] - w).abs() < 1e-9 {
                nn[0] -= 1.0;
            }
            if (x[1] + w).abs() < 1e-9 {
                nn[1] += 1.0;
            }
            if (x[1] - w).abs() < 1e-9 {
                nn[1] -= 1.0;
            }
            let h = (nn[0] * nn[0] + nn[1] * nn[1]).sqrt();
            let nn = [nn[0] / h, nn[1] / h, 0.5];
            let l = norm3(nn);
            let nn = [nn[0] / l, nn[1] / l, nn[2] / l];
            contact_nodes.push(a);
            frames.push(Frame {
                n: nn,
                t1: [-nn[1], nn[0], 0.0],
                t2: [0.0; 3],
            });
            let st = match contact_nodes.len() % 7 {
                0 => NodeStatus::Separated,
                1 | 2 => NodeStatus::Slip,
                3 => NodeStatus::Grazing,
                _ => NodeStatus::Stick,
            };
            if st.pressed() {
                force[a] = [0.03 * nn[0], 0.03 * nn[1], 0.03 * nn[2] + 0.025];
            }
            status.push(st);
        }
    }
    let mut facets = Vec::new();
    for e in mesh.elements() {
        for f in e.kind.facets() {
            let f: Vec<usize> = f.iter().map(|&i| e.nodes[i]).collect();
            let on_side = |c: usize| {
                f.iter().all(|&a| {
                    let x = coords[a];
                    let w = half(x[2]);
                    [(x[0] + w), (x[0] - w), (x[1] + w), (x[1] - w)][c].abs() < 1e-9
                })
            };
            if (0..4).any(on_side) {
                facets.push(f);
            }
        }
    }
    let clamped = (0..coords.len()).filter(|&a| coords[a][2] == 1.0).collect();
    let boundary = boundary(contact_nodes, frames, facets, clamped);
    let von_mises: Vec<f64> = mesh
        .elements()
        .iter()
        .map(|e| {
            let c = e
                .nodes
                .iter()
                .fold([0.0; 3], |s, &a| add3(s, coords[a], 0.125));
            0.3 + c[0].abs().max(c[1].abs()) * (1.2 - c[2])
        })
        .collect();
    let stress = von_mises
        .iter()
        .map(|&v| [-v, -v, -0.3 * v, 0.0, 0.0, 0.0])
        .collect();
    let state = Configuration {
        displacement,
        force,
        stress,
        von_mises,
    };
    Sample {
        mesh,
        boundary,
        status,
        state,
        rays: vec![],
    }
}

fn write_sample(name: &str, svg: &str) {
    if let Some(dir) = std::env::var_os("WEDGED_SVG_SAMPLE_DIR") {
        std::fs::write(std::path::Path::new(&dir).join(name), svg).unwrap();
    }
}

fn render(sample: &Sample, title: &str) -> String {
    let rays: Vec<(usize, &Configuration)> = sample
        .rays
        .iter()
        .enumerate()
        .map(|(k, c)| (k + 1, c))
        .collect();
    let view = View {
        mesh: &sample.mesh,
        boundary: &sample.boundary,
        status: &sample.status,
        state: &sample.state,
        rays: &rays,
        title: title.to_string(),
    };
    svg_string(&view)
}

/// One circle per contact node with its status class, one arrow per pressed node, the legend.
fn check_picture(sample: &Sample, svg: &str) {
    check_xml(svg).unwrap_or_else(|e| panic!("malformed SVG: {e}\n{svg}"));
    assert_eq!(
        count(svg, "<circle class=\"contact "),
        sample.boundary.contact_nodes.len()
    );
    for status in STATUSES {
        let (class, _, _) = status_style(status);
        let expected = sample.status.iter().filter(|&&s| s == status).count();
        assert_eq!(
            count(svg, &format!("class=\"contact status-{class}\"")),
            expected,
            "{class}"
        );
    }
    let pressed = sample.status.iter().filter(|s| s.pressed()).count();
    assert_eq!(count(svg, "<g class=\"reaction\">"), pressed);
    // Every circle and arrow has a tooltip.
    assert!(count(svg, "<title>node ") >= sample.boundary.contact_nodes.len());
    assert!(svg.contains("<g class=\"legend\">"));
    // The legend lists the statuses of the dimension (2D slip+ and slip-, 3D slip), and any
    // other status present.
    let three_d = sample.mesh.dim() == 3;
    for status in STATUSES {
        let listed = sample.status.contains(&status)
            || match status {
                NodeStatus::SlipPlus | NodeStatus::SlipMinus => !three_d,
                NodeStatus::Slip => three_d,
                _ => true,
            };
        assert_eq!(
            svg.contains(&format!(">{} (", status.name())),
            listed,
            "{status:?}"
        );
    }
    assert!(svg.contains("reaction on the body"));
    assert!(svg.contains("von Mises stress"));
    assert!(svg.contains("displacements x "));
}

#[test]
fn svg_sample_2d_trapezoidal_plug() {
    let sample = plug_2d();
    let svg = render(
        &sample,
        "cone 2 of 3, mu = 0.8: 2 rays, 6 contact nodes pressed",
    );
    check_picture(&sample, &svg);
    assert!(svg.contains("clamped"));
    assert!(svg.contains("class=\"hatch\""));
    assert!(svg.contains("class=\"undeformed\""));
    assert!(svg.contains("<title>node 1: separated"));
    write_sample("svg-sample-2d.svg", &svg);
}

#[test]
fn svg_sample_3d_frustum_plug() {
    let sample = plug_3d();
    let svg = render(
        &sample,
        "cone 1 of 1, mu = 0.6: 5 rays, 27 contact nodes pressed",
    );
    check_picture(&sample, &svg);
    assert!(svg.contains("Isometric view from (1, 1, -1), z up"));
    assert!(svg.contains("class=\"far-side\""));
    write_sample("svg-sample-3d.svg", &svg);
}

#[test]
fn svg_degenerate_inputs_do_not_panic() {
    // Zero displacement, zero force, a single element.
    let mesh = Mesh::new(
        2,
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        vec![Element {
            kind: ElementKind::Tri3,
            nodes: vec![0, 1, 2],
        }],
        vec![],
    )
    .unwrap();
    let b = boundary(
        vec![0, 1],
        vec![frame_2d([0.0, 1.0, 0.0]); 2],
        vec![vec![0, 1]],
        vec![],
    );
    let state = Configuration {
        displacement: vec![[0.0; 3]; 3],
        force: vec![[0.0; 3]; 3],
        stress: vec![[0.0; 6]],
        von_mises: vec![0.0],
    };
    let status = [NodeStatus::Stick, NodeStatus::Grazing];
    let view = View {
        mesh: &mesh,
        boundary: &b,
        status: &status,
        state: &state,
        rays: &[],
        title: "zero <state> & nothing".to_string(),
    };
    let svg = svg_string(&view);
    check_xml(&svg).unwrap();
    assert!(svg.contains("no displacement"));
    assert!(svg.contains("No reaction"));
    assert_eq!(count(&svg, "<circle class=\"contact "), 2);
    assert_eq!(count(&svg, "<g class=\"reaction\">"), 0);
    assert!(svg.contains("(uniform)"));
    assert!(svg.contains("zero &lt;state&gt; &amp; nothing"));
    write_sample("svg-sample-degenerate.svg", &svg);

    // NaN displacement at one node, NaN force and stress: those items are skipped.
    let state = Configuration {
        displacement: vec![[0.0, 0.1, 0.0], [f64::NAN, 0.0, 0.0], [0.0, 0.0, 0.0]],
        force: vec![[f64::NAN, 1.0, 0.0], [0.0, 1.0, 0.0], [0.0; 3]],
        stress: vec![[f64::NAN; 6]],
        von_mises: vec![f64::NAN],
    };
    let view = View {
        state: &state,
        ..view
    };
    let svg = svg_string(&view);
    check_xml(&svg).unwrap();
    // NaN may appear in tooltips only, never in coordinates.
    let drawn: String = svg
        .split("<title>")
        .map(|part| part.split_once("</title>").map_or(part, |(_, rest)| rest))
        .collect();
    assert!(!drawn.contains("NaN"), "{drawn}");
    assert_eq!(count(&svg, "<circle class=\"contact "), 1);
    assert_eq!(count(&svg, "<g class=\"reaction\">"), 0);
    assert!(svg.contains("displacements x 1.13"), "{svg}");
    assert!(svg.contains("not available"));

    // Sizes that do not match: an error picture.
    let state = Configuration {
        displacement: vec![[0.0; 3]; 2],
        ..state.clone()
    };
    let view = View {
        state: &state,
        ..view
    };
    let svg = svg_string(&view);
    check_xml(&svg).unwrap();
    assert!(svg.contains("cannot draw this configuration"));
}

#[test]
fn svg_3d_single_tetrahedron() {
    let mesh = Mesh::new(
        3,
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
        vec![Element {
            kind: ElementKind::Tet4,
            nodes: vec![0, 1, 2, 3],
        }],
        vec![],
    )
    .unwrap();
    let b = boundary(
        vec![0, 1, 2],
        vec![frame_2d([0.0, 0.0, 1.0]); 3],
        vec![vec![0, 2, 1]],
        vec![3],
    );
    let state = Configuration {
        displacement: vec![[0.0, 0.0, 0.01], [0.0; 3], [0.0; 3], [0.0; 3]],
        force: vec![[0.0, 0.0, 0.5], [0.1, 0.0, 0.5], [0.0; 3], [0.0; 3]],
        stress: vec![[1.0, 0.0, 0.0, 0.0, 0.0, 0.0]],
        von_mises: vec![1.0],
    };
    let status = [
        NodeStatus::Stick,
        NodeStatus::SlipPlus,
        NodeStatus::Separated,
    ];
    let view = View {
        mesh: &mesh,
        boundary: &b,
        status: &status,
        state: &state,
        rays: &[],
        title: String::new(),
    };
    let svg = svg_string(&view);
    check_xml(&svg).unwrap();
    assert_eq!(count(&svg, "<circle class=\"contact "), 3);
    assert_eq!(count(&svg, "<g class=\"reaction\">"), 2);
    write_sample("svg-sample-tet.svg", &svg);
    // Of the 4 boundary faces, those facing the viewer.
    let faces = svg
        .split("<g class=\"deformed\"")
        .nth(1)
        .unwrap()
        .split("</g>")
        .next()
        .unwrap();
    assert!((1..=3).contains(&count(faces, "<polygon")));
}

#[test]
fn svg_number_formatting() {
    assert_eq!(sig4(0.0), "0");
    assert_eq!(sig4(-0.0), "0");
    assert_eq!(sig4(1234.5678), "1235");
    assert_eq!(sig4(0.012345), "0.01235");
    assert_eq!(sig4(1.5), "1.5");
    assert_eq!(sig4(123456789.0), "1.235e8");
    assert_eq!(sig4(-0.00001234), "-1.234e-5");
    assert_eq!(px(12.04), "12");
    assert_eq!(px(-0.04), "0");
    assert_eq!(round3(1234.5), 1230.0);
    assert_eq!(viridis(0.0), "#440154");
    assert_eq!(viridis(1.0), "#fde725");
    assert_eq!(viridis(f64::NAN), viridis(0.5));
    assert!(check_xml("<a><b/></a>").is_ok());
    assert!(check_xml("<a><b></a>").is_err());
    assert!(check_xml("<a x=1/>").is_err());
    assert!(check_xml("<a>&</a>").is_err());
}
