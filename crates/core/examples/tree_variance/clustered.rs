//! Clustered sets of point lights near the plane, which no preset resembles: where the
//! nearest few lights of a cluster give a point most of its light, and a tree's
//! representative lights judge a cluster's parts poorly.

use glam::{DVec3, dvec2, dvec3};
use lightpick_core::scene::{ReceiverPlane, Scene};

use super::SplitMix;

/// A scene `name` of point lights over `[-8, 8]²` on 256 × 256 pixels.
fn points(name: &str, lights: Vec<(DVec3, f64)>) -> Result<Scene, Box<dyn std::error::Error>> {
    let plane = ReceiverPlane {
        min: dvec2(-8.0, -8.0),
        max: dvec2(8.0, 8.0),
        width: 256,
        height: 256,
    };
    let (positions, powers) = lights.into_iter().unzip();
    Ok(Scene::from_parts(name, plane, positions, powers)?)
}

/// 24 clusters of 400 lights (σ = 0.3 m) 0.05–0.3 m above the plane, powers over two
/// decades.
fn clusters_low() -> Result<Scene, Box<dyn std::error::Error>> {
    let mut d = SplitMix(21);
    let mut lights = Vec::new();
    for _ in 0..24 {
        let (cx, cy) = (d.range(-7.0, 7.0), d.range(-7.0, 7.0));
        for _ in 0..400 {
            let (x, y) = (cx + d.normal(0.3), cy + d.normal(0.3));
            let z = d.range(0.05, 0.3);
            lights.push((dvec3(x, y, z), 10f64.powf(d.range(-1.0, 1.0))));
        }
    }
    points("clusters-low", lights)
}

/// 100 chandeliers of 100 equal lights (σ = 0.1 m) hung 0.5–1 m above the plane.
fn chandeliers() -> Result<Scene, Box<dyn std::error::Error>> {
    let mut d = SplitMix(22);
    let mut lights = Vec::new();
    for _ in 0..100 {
        let centre = dvec3(d.range(-7.5, 7.5), d.range(-7.5, 7.5), d.range(0.5, 1.0));
        for _ in 0..100 {
            let z = centre.z + d.normal(0.05).abs();
            let at = dvec3(centre.x + d.normal(0.1), centre.y + d.normal(0.1), z);
            lights.push((at, 1.0));
        }
    }
    points("chandeliers", lights)
}

/// 40 strips of 250 equal lights along straight lines 2–6 m long, 0.1 m above the plane.
fn strips() -> Result<Scene, Box<dyn std::error::Error>> {
    let mut d = SplitMix(23);
    let mut lights = Vec::new();
    for _ in 0..40 {
        let (x0, y0) = (d.range(-7.0, 7.0), d.range(-7.0, 7.0));
        let (angle, length) = (d.range(0.0, std::f64::consts::PI), d.range(2.0, 6.0));
        for i in 0..250 {
            let t = length * (f64::from(i) / 249.0 - 0.5);
            let at = dvec3(x0 + t * angle.cos(), y0 + t * angle.sin(), 0.1);
            lights.push((at, 1.0));
        }
    }
    points("strips", lights)
}

/// The three sets.
pub fn all() -> Result<[Scene; 3], Box<dyn std::error::Error>> {
    Ok([clusters_low()?, chandeliers()?, strips()?])
}

/// The set called `name`, if it is one of them.
pub fn by_name(name: &str) -> Result<Option<Scene>, Box<dyn std::error::Error>> {
    Ok(match name {
        "clusters-low" => Some(clusters_low()?),
        "chandeliers" => Some(chandeliers()?),
        "strips" => Some(strips()?),
        _ => None,
    })
}
