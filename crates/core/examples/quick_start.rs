//! Quick start: build an alias table, sample it one at a time and in a batch, render the
//! worked example on the CPU, and write the table diagram and the image to PNG.
//!
//! `cargo run -p lightpick-core --release --example quick_start [OUT_DIR]`

use lightpick_core::draw::{Style, auto_exposure, fraction_denominator, table_diagram, write_png};
use lightpick_core::render::{CpuRenderer, Reference, rmse, tonemap_rgba8};
use lightpick_core::scene::Scene;
use lightpick_core::{AliasTable, LightPowers, Rng, Scheme};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::path::PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| ".".into()));
    std::fs::create_dir_all(&out)?;

    // The worked example: powers 2, 5, 20.
    let powers = LightPowers::new(vec![2.0, 5.0, 20.0])?;
    let exact = AliasTable::build_exact(&powers);
    println!(
        "exact f64 table: thresholds {:?}, aliases {:?}",
        exact.thresholds(),
        exact.aliases()
    );
    let table = AliasTable::build(&powers);
    println!(
        "integer table (the samplers' default): masses {:?} of 3·2^32",
        table.packed_masses()
    );

    let mut rng = Rng::new(2026, 0);
    let mut picks = vec![0u32; 1 << 20];
    table.sample_into(&mut picks, &mut rng);
    let mut counts = [0u64; 3];
    for &light in &picks {
        counts[light as usize] += 1;
    }
    for (i, (&count, p)) in counts.iter().zip(table.pmf_slice()).enumerate() {
        println!(
            "light {i}: {count} picks, expected {:.0}",
            p * picks.len() as f64
        );
    }

    let diagram = table_diagram(&exact, fraction_denominator(&powers), &Style::default())?;
    write_png(&diagram, out.join("seed_table.png"))?;

    let scene = Scene::preset("worked-example")?;
    let mut renderer = CpuRenderer::new(&scene, Scheme::Alias, 7);
    renderer.accumulate(64);
    let reference = Reference::compute(&scene);
    println!(
        "worked example at 64 spp: RMSE {:.3e}",
        rmse(renderer.accumulator(), &reference)
    );
    let exposure = reference.image().map_or(1.0, auto_exposure);
    let rgba = tonemap_rgba8(&renderer.accumulator().image(), exposure);
    let (w, h) = (scene.plane.width, scene.plane.height);
    image::save_buffer(
        out.join("seed_render.png"),
        &rgba,
        w,
        h,
        image::ColorType::Rgba8,
    )?;
    println!(
        "wrote {} and {}",
        out.join("seed_table.png").display(),
        out.join("seed_render.png").display()
    );
    Ok(())
}
