//! Light sets from outside: glTF 2.0 (`.gltf`, `.glb`), CSV lists and the one loader, on
//! the fixtures of `tests/fixtures/lights/` and on malformed files written here.

#![allow(clippy::unwrap_used)] // Tests unwrap: a failure is the test failing.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
use std::path::PathBuf;

use glam::{DVec2, DVec3, dvec3};
use lightpick_core::scene::{
    Emission, LoadOptions, MAX_LIGHTS, Scene, SceneError, SceneFormat, Spot, load, load_bytes,
};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/fixtures/lights")
        .join(name)
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).abs().max_element() <= 1e-6 * b.abs().max_element().max(1.0)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// A spot's power from its intensity, as the import computes it:
/// `2π·I·Y·[(1 − cos θi) + (cos θi − cos θo)/3]`.
fn spot_power(i: f64, y: f64, inner: f64, outer: f64) -> f64 {
    2.0 * PI * i * y * ((1.0 - inner.cos()) + (inner.cos() - outer.cos()) / 3.0)
}

#[test]
fn the_hierarchy_fixture_imports_every_light_where_the_nodes_put_it() {
    let loaded = load(fixture("hierarchy.gltf"), &LoadOptions::default()).unwrap();
    let (scene, report) = (&loaded.scene, &loaded.report);
    assert_eq!(report.format, SceneFormat::Gltf);
    assert_eq!((report.points, report.spots), (3, 2));
    assert_eq!(report.skipped.len(), 1);
    assert_eq!(report.skipped[0].name, "Sun");
    assert!(report.skipped[0].reason.contains("directional"));
    assert_eq!(
        report.summary(),
        "5 lights: 3 points, 2 spots; skipped 1 directional light 'Sun'"
    );
    assert_eq!(scene.name, "hierarchy");
    // Depth first from the roots: Lamp A, Spot Node, Instance (under Root); the unnamed
    // ranged light (light's own name); Tilted spot. The node outside the scene is not read.
    let names: Vec<Option<&str>> = (0..5).map(|i| scene.name_of(i)).collect();
    assert_eq!(
        names,
        [
            Some("Lamp A"),
            Some("Spot Node"),
            Some("Instance"),
            Some("Ranged light"),
            Some("Tilted spot")
        ]
    );
    // glTF (x, y, z) → lightpick (x, −z, y), through translation, rotation, scale, matrix.
    let expected = [
        dvec3(1.0, 0.0, 2.0), // Root (0,2,0) + (1,0,0)
        dvec3(0.0, 2.0, 2.0), // Arm: scale 2, 90° about +Y: (1,0,0) → (0,0,−2)
        dvec3(6.0, 0.0, 2.0), // matrix (0,0,3) → scaled (0,0,6) → rotated (6,0,0)
        dvec3(-2.0, -1.0, 1.0),
        dvec3(0.0, 0.0, 3.0),
    ];
    for (got, want) in scene.positions.iter().zip(expected) {
        assert!(close(*got, want), "{got} vs {want}");
    }
    let p = scene.powers.as_slice();
    // Point lights: Φ = 4π·I·Y (white: Y = 1); the instanced bulb twice.
    assert!(rel(p[0], 4.0 * PI * 10.0) < 1e-12);
    assert_eq!(p[0], p[2]);
    assert!(rel(p[3], 4.0 * PI * 2.0) < 1e-12);
    // Spots: defaults θi = 0, θo = π/4; and a coloured one.
    assert!(rel(p[1], spot_power(100.0, 1.0, 0.0, FRAC_PI_4)) < 1e-6);
    let y = 0.2126 + 0.7152 * 0.5 + 0.0722 * 0.25;
    assert!(rel(p[4], spot_power(50.0, y, 0.2, 0.6)) < 1e-6);
    let emission = scene.emission.as_ref().unwrap();
    let spot = emission[1].spot().unwrap();
    assert_eq!(
        (spot.inner_cone, spot.outer_cone as f32),
        (0.0, FRAC_PI_4 as f32)
    );
    // Scale does not change the cone; its world axis is local −Z turned by the arm: −x.
    assert!(
        close(emission[1].axis(), dvec3(-1.0, 0.0, 0.0)),
        "{}",
        emission[1].axis()
    );
    assert!(
        close(emission[4].axis(), dvec3(0.0, 0.0, -1.0)),
        "{}",
        emission[4].axis()
    );
    assert_eq!(emission[3].range(), Some(5.0));
    assert!(emission[0].is_point() && emission[2].is_point());
    // The receiver is the ground; the plane covers the lights' footprint.
    let plane = &scene.plane;
    for q in scene.positions.iter() {
        assert!(plane.min.x < q.x && q.x < plane.max.x && plane.min.y < q.y && q.y < plane.max.y);
    }
}

#[test]
fn the_glb_holds_the_same_scene_and_so_does_its_json_round_trip() {
    let gltf = load(fixture("hierarchy.gltf"), &LoadOptions::default()).unwrap();
    let glb = load(fixture("hierarchy.glb"), &LoadOptions::default()).unwrap();
    assert_eq!(glb.report.format, SceneFormat::Glb);
    assert_eq!(glb.scene, gltf.scene);
    assert_eq!(glb.report.skipped, gltf.report.skipped);
    // As lightpick JSON (names, spots and ranges included) and back: the same scene.
    let again = Scene::from_json_str(&gltf.scene.to_json()).unwrap();
    assert_eq!(again, gltf.scene);
}

#[test]
fn a_floor_moves_the_receiver_up() {
    let floor = load(fixture("hierarchy.glb"), &LoadOptions { floor: Some(1.5) }).unwrap();
    let ground = load(fixture("hierarchy.glb"), &LoadOptions::default()).unwrap();
    for (a, b) in floor
        .scene
        .positions
        .iter()
        .zip(ground.scene.positions.iter())
    {
        assert_eq!(a.z, b.z - 1.5);
        assert_eq!(a.truncate(), b.truncate());
    }
    // The ranged light at height 1 is now below the receiver: it lights nothing.
    let x = floor.scene.positions[3].truncate();
    assert_eq!(floor.scene.light_term(3, x), 0.0);
}

#[test]
fn csv_lists_load_with_names() {
    let loaded = load(fixture("lamps.csv"), &LoadOptions::default()).unwrap();
    assert_eq!(loaded.report.format, SceneFormat::Csv);
    assert_eq!(loaded.scene.powers.as_slice(), [800.0, 450.0, 120.0]);
    assert_eq!(loaded.scene.name_of(1), Some("Desk"));
    assert!(
        loaded.scene.emission.is_none(),
        "point lights keep no emission data"
    );
    assert_eq!(loaded.report.summary(), "3 lights");
}

/// The power the import gives a spot is its intensity integrated over the sphere: `I·Y·t²`
/// summed by the midpoint rule in `cos α` over `[cos θo, 1]`, whose error is at most one
/// cell's width times the range of `t²` (monotone): `2π·I·Y·h`.
#[test]
fn a_spots_power_is_its_intensity_integrated_over_the_sphere() {
    for (inner, outer) in [(0.0, FRAC_PI_4), (0.2, 0.6), (0.5, FRAC_PI_2), (0.0, 0.02)] {
        let text = format!(
            r#"{{"asset":{{"version":"2.0"}},"extensions":{{"KHR_lights_punctual":{{"lights":[
            {{"type":"spot","intensity":7,"spot":{{"innerConeAngle":{inner},"outerConeAngle":{outer}}}}}]}}}},
            "nodes":[{{"translation":[0,1,0],"extensions":{{"KHR_lights_punctual":{{"light":0}}}}}}]}}"#
        );
        let scene = load_bytes(text.as_bytes(), "s", Some("gltf"), &LoadOptions::default())
            .unwrap()
            .scene;
        let (inner, outer) = (f64::from(inner as f32), f64::from(outer as f32));
        let outer = outer.min(FRAC_PI_2);
        let (ci, co) = (inner.cos(), outer.cos());
        let steps = 400_000;
        let h = (1.0 - co) / f64::from(steps);
        let mut integral = 0.0;
        for k in 0..steps {
            let c = co + (f64::from(k) + 0.5) * h;
            let t = ((c - co) / (ci - co)).clamp(0.0, 1.0);
            integral += 7.0 * t * t * h;
        }
        let numeric = 2.0 * PI * integral;
        let bound = 2.0 * PI * 7.0 * h + 1e-9 * numeric;
        let power = scene.powers.as_slice()[0];
        assert!(
            (power - numeric).abs() <= bound,
            "({inner}, {outer}): {power} vs {numeric}"
        );
    }
}

/// A spot's irradiance is the point light's of the same intensity times `t²`, and a range
/// multiplies it by `clamp(1 − (d/r)⁴, 0, 1)`: checked through `Scene::light_term` against
/// the formulas written out here.
#[test]
fn spot_and_range_terms_follow_their_formulas() {
    let (inner, outer, r) = (0.3, 0.7, 3.0);
    let e = Emission::new(
        Some(Spot {
            direction: dvec3(0.0, 0.0, -2.0),
            inner_cone: inner,
            outer_cone: outer,
        }),
        Some(r),
    )
    .unwrap();
    let light = dvec3(0.5, -0.5, 2.0);
    for x in [
        DVec2::new(0.5, -0.5),
        DVec2::new(1.0, 0.0),
        DVec2::new(1.6, -0.5),
        DVec2::new(2.5, 1.0),
        DVec2::new(-3.0, 2.0),
    ] {
        let d = x.extend(0.0) - light;
        let dist = d.length();
        let cos_alpha = -d.z / dist;
        let t = ((cos_alpha - outer.cos()) / (inner.cos() - outer.cos())).clamp(0.0, 1.0);
        let window = (1.0 - (dist / r).powi(4)).clamp(0.0, 1.0);
        // Point light of intensity Φ·g/4π: E = I·cos θ/d², cos θ = z/d.
        let point = light.z / dist.powi(3) / (4.0 * PI);
        let want = point * e.gain() * t * t * window;
        let got = lightpick_core::scene::light_term(light, Some(&e), x);
        assert!(
            (got - want).abs() <= 1e-14 * want.max(1e-300),
            "{x}: {got} vs {want}"
        );
    }
}

fn gltf_err(text: &str) -> String {
    match load_bytes(
        text.as_bytes(),
        "bad",
        Some("gltf"),
        &LoadOptions::default(),
    ) {
        Ok(l) => panic!("accepted: {:?}", l.report),
        Err(e) => e.to_string(),
    }
}

/// A document with one light `light` (JSON object) on one node `node_extra`.
fn one_light(light: &str, node_extra: &str) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"extensions":{{"KHR_lights_punctual":{{"lights":[{light}]}}}},
        "nodes":[{{"name":"N"{node_extra},"extensions":{{"KHR_lights_punctual":{{"light":0}}}}}}]}}"#
    )
}

#[test]
fn malformed_json_and_glb_containers_are_named() {
    let truncated = &std::fs::read_to_string(fixture("hierarchy.gltf")).unwrap()[..500];
    let e = gltf_err(truncated);
    assert!(e.starts_with("gltf: "), "{e}");
    let glb = std::fs::read(fixture("hierarchy.glb")).unwrap();
    let glb_err = |bytes: &[u8]| {
        load_bytes(bytes, "bad", Some("glb"), &LoadOptions::default())
            .unwrap_err()
            .to_string()
    };
    let mut wrong_magic = glb.clone();
    wrong_magic[0] = b'x';
    assert_eq!(
        glb_err(&wrong_magic),
        r#"glb: wrong magic "xlTF" (expected "glTF")"#
    );
    let mut long = glb.clone();
    long[8..12].copy_from_slice(&(glb.len() as u32 + 4).to_le_bytes());
    assert_eq!(
        glb_err(&long),
        format!(
            "glb: the header's length {} differs from the file's {} bytes",
            glb.len() + 4,
            glb.len()
        )
    );
    let mut chunk = glb.clone();
    chunk[12..16].copy_from_slice(&(10_000u32).to_le_bytes());
    assert!(glb_err(&chunk).contains("its length 10000 runs past the file's end"));
    assert!(glb_err(&glb[..7]).starts_with("glb: truncated header"));
    // Every prefix of the file is refused with a message, none panics.
    for end in 0..glb.len() {
        assert!(load_bytes(&glb[..end], "p", Some("glb"), &LoadOptions::default()).is_err());
    }
}

#[test]
fn bad_lights_and_nodes_are_named() {
    let e = gltf_err(&one_light(r#"{"type":"point"}"#, "").replace(r#""light":0"#, r#""light":3"#));
    assert!(
        e.starts_with("gltf: invalid glTF: nodes[0].extensions.") && e.contains("light"),
        "{e}"
    );
    let e = gltf_err(&one_light(r#"{"type":"point","intensity":-3}"#, ""));
    assert_eq!(
        e,
        "nodes[0] 'N' → KHR_lights_punctual.lights[0].intensity: negative (-3)"
    );
    // Beyond f32: JSON numbers that no f32 holds are refused by the parser, with the place.
    let e = gltf_err(&one_light(r#"{"type":"point","intensity":1e39}"#, ""));
    assert!(
        e.starts_with("gltf: number out of range at line 1 column"),
        "{e}"
    );
    // JSON has no NaN: the token is refused by the parser, with its line.
    let e = gltf_err(&one_light(r#"{"type":"point","intensity":NaN}"#, ""));
    assert!(e.starts_with("gltf: ") && e.contains("line"), "{e}");
    let e = gltf_err(&one_light(r#"{"type":"point","color":[1,-1,1]}"#, ""));
    assert!(
        e.contains(".color[1]: must be finite and non-negative"),
        "{e}"
    );
    for (inner, outer) in [(0.5, 0.5), (0.6, 0.4), (-0.1, 0.5), (0.1, 1.7)] {
        let e = gltf_err(&one_light(
            &format!(
                r#"{{"type":"spot","spot":{{"innerConeAngle":{inner},"outerConeAngle":{outer}}}}}"#
            ),
            "",
        ));
        assert!(
            e.contains(".spot: cones must satisfy 0 ≤ inner_cone < outer_cone ≤ π/2"),
            "{e}"
        );
    }
    let e = gltf_err(&one_light(r#"{"type":"point","range":0}"#, ""));
    assert!(
        e.contains(".range: must be finite and positive (got 0)"),
        "{e}"
    );
    // Matrices of scale 3e38 nested ten deep overflow f64 in the composed world transform
    // (and inf·0 is NaN): the node where it happens is named.
    let big = "[3e38,0,0,0, 0,3e38,0,0, 0,0,3e38,0, 0,0,0,1]";
    let nodes: Vec<String> = (0..10)
        .map(|i| {
            let tail = if i == 9 {
                r#""extensions":{"KHR_lights_punctual":{"light":0}}"#.to_owned()
            } else {
                format!(r#""children":[{}]"#, i + 1)
            };
            format!(r#"{{"name":"M{i}","matrix":{big},{tail}}}"#)
        })
        .collect();
    let text = format!(
        r#"{{"asset":{{"version":"2.0"}},"extensions":{{"KHR_lights_punctual":{{"lights":[{{"type":"point"}}]}}}},"nodes":[{}]}}"#,
        nodes.join(",")
    );
    let e = gltf_err(&text);
    assert_eq!(
        e,
        "nodes[8] 'M8'.matrix: the world transform is not finite (NaN or overflow)"
    );
    let e = gltf_err(&one_light(r#"{"type":"directional"}"#, ""));
    assert!(
        e.contains("no point or spot light") && e.contains("skipped 1 directional"),
        "{e}"
    );
}

/// Nodes `0 … n−1`, each the child of the one before, the last holding the light.
fn chain(n: usize, extra_children: &[(usize, usize)]) -> String {
    let mut nodes = Vec::with_capacity(n);
    for i in 0..n {
        let mut children: Vec<usize> = (i + 1 < n).then_some(i + 1).into_iter().collect();
        children.extend(
            extra_children
                .iter()
                .filter(|(p, _)| *p == i)
                .map(|(_, c)| *c),
        );
        let light = if i + 1 == n {
            r#","extensions":{"KHR_lights_punctual":{"light":0}}"#
        } else {
            ""
        };
        nodes.push(format!(
            r#"{{"translation":[0,0.001,0],"children":{children:?}{light}}}"#
        ));
    }
    format!(
        r#"{{"asset":{{"version":"2.0"}},"extensions":{{"KHR_lights_punctual":{{"lights":[{{"type":"point"}}]}}}},
        "scenes":[{{"nodes":[0]}}],"nodes":[{}]}}"#,
        nodes.join(",")
    )
}

#[test]
fn cycles_two_parents_and_deep_hierarchies() {
    // 0 → 1 → 2 and 2 → 1: node 1 has two parents.
    let e = gltf_err(&chain(3, &[(2, 1)]));
    assert!(e.contains("has two parents"), "{e}");
    // 1 → 2 → 1 beside the root 0: each node has one parent, and the graph a cycle.
    let cycle = r#"{"asset":{"version":"2.0"},"extensions":{"KHR_lights_punctual":{"lights":[{"type":"point"}]}},
        "scenes":[{"nodes":[0]}],"nodes":[{"translation":[0,1,0],"extensions":{"KHR_lights_punctual":{"light":0}}},
        {"name":"A","children":[2]},{"name":"B","children":[1]}]}"#;
    let e = gltf_err(cycle);
    assert!(
        e.ends_with("is its own ancestor: the node graph has a cycle"),
        "{e}"
    );
    // 10^5 nodes deep: read without recursion; the light sits 100 units up.
    let deep = load_bytes(
        chain(100_000, &[]).as_bytes(),
        "deep",
        Some("gltf"),
        &LoadOptions::default(),
    )
    .unwrap()
    .scene;
    assert_eq!(deep.light_count(), 1);
    assert!(
        (deep.positions[0].z - 100.0).abs() < 1e-2,
        "{}",
        deep.positions[0]
    );
}

#[test]
fn more_lights_than_a_scene_may_hold_are_refused_before_reading_them() {
    let mut text = String::with_capacity(8 * (MAX_LIGHTS + 1));
    for _ in 0..=MAX_LIGHTS {
        text.push_str("0 0 1 1\n");
    }
    let e = load_bytes(
        text.as_bytes(),
        "many",
        Some("csv"),
        &LoadOptions::default(),
    )
    .unwrap_err();
    assert!(
        matches!(&e, SceneError::OutOfRange { field, .. } if field == "lights (count)"),
        "{e}"
    );
}

/// `stage.glb` is the `stage` preset written as glTF (positions turned to +Y up, each spot's
/// node rotated so that its −Z is the spot's axis, intensity `Φ/(2π·[(1 − cos θi) +
/// (cos θi − cos θo)/3])`, plus a directional sun): read back, it is the preset's scene up
/// to the file's `f32` (positions, rotations, intensities) and its 4-decimal intensities.
#[test]
fn the_stage_as_gltf_is_the_stage_preset() {
    let glb = load(fixture("stage.glb"), &LoadOptions::default()).unwrap();
    let preset = Scene::preset("stage").unwrap();
    assert_eq!(glb.report.skipped.len(), 1);
    assert_eq!(glb.scene.light_count(), preset.light_count());
    for i in 0..preset.light_count() {
        assert!(
            close(glb.scene.positions[i], preset.positions[i]),
            "light {i}"
        );
        let (a, b) = (glb.scene.powers.as_slice()[i], preset.powers.as_slice()[i]);
        assert!(rel(a, b) < 1e-5, "light {i}: power {a} vs {b}");
        let (ea, eb) = (
            glb.scene.emission_of(i).unwrap(),
            preset.emission_of(i).unwrap(),
        );
        assert!(ea.axis().angle_between(eb.axis()) < 1e-6, "light {i}: axis");
        assert_eq!(glb.scene.name_of(i), preset.name_of(i));
    }
}
