//! Scene files through the binary: `lightpick scene` (text, the JSON contract, `--out`),
//! `--scene` of every format and `--floor` on `render`, `plot` and `bench`, `lightpick FILE`,
//! and bad files (one `error:` line, exit code 2).

#![allow(clippy::unwrap_used)] // Tests unwrap: a failure is the test failing.

use crate::common::{
    assert_error, bench_json, fixture, json, lightpick_headless, run_ok, scratch, scratch_file,
};

#[test]
fn scene_prints_the_json_contract() {
    let glb = fixture("hierarchy.glb");
    let v = json(&["scene", "--scene", &glb, "--json"]);
    assert_eq!(v["name"], "hierarchy");
    for key in ["min", "max", "width", "height"] {
        assert!(v["plane"].get(key).is_some(), "plane.{key}");
    }
    let lights = v["lights"].as_array().unwrap();
    assert_eq!(lights.len(), 5);
    assert_eq!(lights[0]["name"], "Lamp A");
    assert_eq!(lights[0]["position"], serde_json::json!([1.0, 0.0, 2.0]));
    assert!(lights[0].get("spot").is_none() && lights[0].get("range").is_none());
    let spot = &lights[1]["spot"];
    let direction: Vec<f64> = spot["direction"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d.as_f64().unwrap())
        .collect();
    assert!(
        (direction[0] + 1.0).abs() < 1e-6 && direction[1].abs() < 1e-6,
        "{direction:?}"
    );
    assert_eq!(spot["inner_cone"], 0.0);
    assert!((spot["outer_cone"].as_f64().unwrap() - std::f64::consts::FRAC_PI_4).abs() < 1e-7);
    assert_eq!(lights[3]["range"], 5.0);
    let import = &v["import"];
    assert_eq!(import["format"], "glb");
    assert_eq!(
        (import["points"].as_u64(), import["spots"].as_u64()),
        (Some(3), Some(2))
    );
    assert_eq!(import["skipped"][0]["name"], "Sun");
    assert!(
        import["skipped"][0]["reason"]
            .as_str()
            .unwrap()
            .contains("directional")
    );
    // --floor: positions after the floor.
    let v = json(&["scene", "--scene", &glb, "--floor", "0.5", "--json"]);
    assert_eq!(
        v["lights"][0]["position"],
        serde_json::json!([1.0, 0.0, 1.5])
    );
}

#[test]
fn scene_text_and_out_round_trip() {
    let dir = scratch("scene-out");
    let out = dir.join("hierarchy.json");
    let run = run_ok(&[
        "scene",
        "--scene",
        &fixture("hierarchy.gltf"),
        "--out",
        out.to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&run.stdout);
    assert!(
        text.contains("5 lights: 3 points, 2 spots; skipped 1 directional light 'Sun' (gltf)"),
        "{text}"
    );
    assert!(text.contains("skipped 'Sun': directional light"), "{text}");
    // The JSON written reads back as the same lights.
    let a = json(&["scene", "--scene", &fixture("hierarchy.gltf"), "--json"]);
    let b = json(&["scene", "--scene", out.to_str().unwrap(), "--json"]);
    assert_eq!(a["lights"], b["lights"]);
    assert_eq!(b["import"]["format"], "json");
    let csv = json(&["scene", "--scene", &fixture("lamps.csv"), "--json"]);
    assert_eq!(csv["lights"][2]["name"], "Shelf");
    assert_eq!(csv["import"]["format"], "csv");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_command_reads_every_format_and_takes_a_floor() {
    let glb = fixture("hierarchy.glb");
    let render = json(&[
        "render", "--scene", &glb, "--floor", "0.25", "--spp", "4", "--width", "24", "--height",
        "16", "--device", "cpu", "--scheme", "spatial", "--json",
    ]);
    assert_eq!(render["spp"], 4);
    assert!(render["rmse"].as_f64().unwrap().is_finite());
    let table = json(&["table", "--scene", &fixture("lamps.csv"), "--json"]);
    assert_eq!(table["n"], 3);
    let dir = scratch("scene-plot");
    let png = dir.join("sheet.png");
    run_ok(&[
        "plot",
        "sheet",
        "--scene",
        &glb,
        "--floor",
        "0.25",
        "--spp",
        "2",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(image::open(&png).is_ok());
    let bench = bench_json(&[
        "--presets",
        "none",
        "--scene",
        &glb,
        "--floor",
        "0.25",
        "--spp",
        "8",
    ]);
    assert_eq!(bench["renders"][0]["preset"], "hierarchy.glb");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_scene_files_are_one_error_line() {
    let dir = scratch("bad-scenes");
    let write = |name: &str, bytes: &[u8]| {
        let p = dir.join(name);
        std::fs::write(&p, bytes).unwrap();
        p.to_str().unwrap().to_owned()
    };
    let truncated = write(
        "truncated.gltf",
        &std::fs::read(fixture("hierarchy.gltf")).unwrap()[..300],
    );
    assert_error(&["scene", "--scene", &truncated], "gltf: ");
    let mut glb = std::fs::read(fixture("hierarchy.glb")).unwrap();
    glb[0] = b'G';
    let magic = write("magic.glb", &glb);
    assert_error(&["scene", "--scene", &magic], "glb: wrong magic");
    let mut glb = std::fs::read(fixture("hierarchy.glb")).unwrap();
    glb[12..16].copy_from_slice(&9999u32.to_le_bytes());
    let chunk = write("chunk.glb", &glb);
    assert_error(&["render", "--scene", &chunk], "runs past the file's end");
    let csv = write("bad.csv", b"0 0 1 2\n0 0 one 2\n");
    assert_error(
        &["scene", "--scene", &csv],
        "line 2, z: not a number ('one')",
    );
    assert_error(&["scene", "--scene", &truncated, "--floor", "nan"], "floor");
    assert_error(&["scene", "--floor", "1"], "--floor: give a scene");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn lightpick_file_parses_as_a_file_to_open() {
    // Without a display the app cannot open, but the file is read first: a bad one is named,
    // a good one reaches the display check; a word that is no file and no subcommand says so.
    let good = lightpick_headless(&[&fixture("lamps.csv")]);
    let stderr = String::from_utf8_lossy(&good.stderr);
    assert_eq!(good.status.code(), Some(2));
    assert!(stderr.contains("no display found"), "{stderr}");
    let missing = lightpick_headless(&["frobnicate"]);
    let stderr = String::from_utf8_lossy(&missing.stderr);
    assert_eq!(missing.status.code(), Some(2));
    assert!(
        stderr.starts_with("error: 'frobnicate' is neither a subcommand nor a file"),
        "{stderr}"
    );
}

#[test]
fn lightpick_file_names_a_bad_file_as_typed() {
    // `lightpick FILE` typed no `--scene`: the error names the file alone.
    let bad = scratch_file("open-bad", "bad.csv", "x,y\n1,2,3\n");
    let path = bad.to_str().unwrap();
    let out = lightpick_headless(&[path]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr:?}");
    assert!(
        stderr.starts_with(&format!("error: {path}: line 1: ")),
        "{stderr}"
    );
    assert!(!stderr.contains("--scene"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    // `--scene FILE` keeps the flag it was given.
    assert_error(
        &["scene", "--scene", path],
        &format!("error: --scene {path}: line 1: "),
    );
}
