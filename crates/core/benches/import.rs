//! Import speed: `scene::load_bytes` of a `.glb` holding 10^6 light nodes (half points,
//! half spots, all instancing two lights), the goal being ≤ 2 s in release. A benchmark,
//! not a timed test. Run with `cargo bench -p lightpick-core --bench import`;
//! `LIGHTPICK_IMPORT_LIGHTS=100000` changes the count.

use std::fmt::Write as _;
use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use lightpick_core::Rng;
use lightpick_core::scene::{LoadOptions, load_bytes};

/// A GLB of `n` nodes, each at a random place with one of two lights, all roots of scene 0.
fn glb(n: usize) -> Vec<u8> {
    let mut rng = Rng::new(7, 0);
    let mut nodes = String::with_capacity(100 * n);
    for i in 0..n {
        let _ = write!(
            nodes,
            r#"{}{{"translation":[{:.4},{:.4},{:.4}],"extensions":{{"KHR_lights_punctual":{{"light":{}}}}}}}"#,
            if i == 0 { "" } else { "," },
            100.0 * rng.next_unit() - 50.0,
            0.5 + 4.5 * rng.next_unit(),
            100.0 * rng.next_unit() - 50.0,
            i % 2
        );
    }
    let roots: Vec<String> = (0..n).map(|i| i.to_string()).collect();
    let mut json = format!(
        r#"{{"asset":{{"version":"2.0"}},"extensionsUsed":["KHR_lights_punctual"],"extensions":{{"KHR_lights_punctual":{{"lights":[{{"type":"point","intensity":1}},{{"type":"spot","intensity":5,"spot":{{"outerConeAngle":0.5}}}}]}}}},"scene":0,"scenes":[{{"nodes":[{}]}}],"nodes":[{nodes}]}}"#,
        roots.join(",")
    )
    .into_bytes();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut out = Vec::with_capacity(json.len() + 20);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&((json.len() + 20) as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(&0x4E4F_534Au32.to_le_bytes());
    out.extend_from_slice(&json);
    out
}

fn import(c: &mut Criterion) {
    let n: usize = std::env::var("LIGHTPICK_IMPORT_LIGHTS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let bytes = glb(n);
    let mut group = c.benchmark_group("import");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(20));
    group.bench_function(format!("glb/{n}"), |b| {
        b.iter(|| {
            let loaded = load_bytes(
                black_box(&bytes),
                "bench",
                Some("glb"),
                &LoadOptions::default(),
            )
            .expect("a valid file");
            assert_eq!(loaded.scene.light_count(), n);
            loaded
        });
    });
    group.finish();
}

criterion_group!(benches, import);
criterion_main!(benches);
