//! glTF 2.0 lights (`KHR_lights_punctual`) as a lightpick scene.
//!
//! * Every node of the document's default scene (else scene 0; with no scene, every node
//!   without a parent) is visited from its root, depth first with an explicit stack (a
//!   hierarchy 10^5 nodes deep is fine), composing world transforms in `f64` from the
//!   nodes' TRS or `matrix`. Each node that references a light adds one light: a light
//!   instanced by several nodes appears once per node.
//! * Axes: glTF is +Y up, lightpick's receiver is `z = 0` with normal +z: a glTF point
//!   `(x, y, z)` becomes `(x, −z, y)`, the Z-up world Blender shows (a rotation, so spots
//!   keep their handedness). A spot's axis is the node's world transform of local −Z,
//!   normalized (scale changes neither intensity nor cone).
//! * Power, in lumens, from the intensity `I` (candela) and the luminance of `color`,
//!   `Y = 0.2126 R + 0.7152 G + 0.0722 B`: a point light `Φ = 4π·I·Y`; a spot
//!   `Φ = 2π·I·Y·[(1 − cos θi) + (cos θi − cos θo)/3]`, the exact integral of its falloff
//!   `t²` over the sphere ([`crate::scene::Emission`]), so that its on-axis intensity is
//!   `I·Y` again.
//! * Directional lights are not point lights: each is skipped and reported by name.
//!
//! A malformed file is refused with one message naming the problem and where: the GLB
//! header or chunk, the JSON (its line), the node or light and field, a node with two
//! parents, a cycle, a transform that is not finite.

use glam::{DMat4, DQuat, DVec3};

use super::count::check_count;
use super::format::SceneFormat;
use super::plane::{IMPORT_PLANE_PIXELS, footprint_plane};
use super::report::{ImportReport, SkippedLight};
use crate::scene::{Emission, Scene, SceneError, Spot};

/// glTF's `(x, y, z)` (+Y up) as lightpick's (+Z up): `(x, −z, y)`.
pub fn to_lightpick(v: DVec3) -> DVec3 {
    // `0.0 - z` rather than `-z`: a light on the axis gets y = 0, not −0.
    DVec3::new(v.x, 0.0 - v.z, v.y)
}

/// The luminance `Y = 0.2126 R + 0.7152 G + 0.0722 B` of a linear RGB colour.
pub fn luminance([r, g, b]: [f64; 3]) -> f64 {
    0.2126 * r + 0.7152 * g + 0.0722 * b
}

/// A spot's power per unit `I·Y`: `2π·[(1 − cos θi) + (cos θi − cos θo)/3]`, with
/// `1 − cos θi` and `cos θi − cos θo` computed without cancellation.
pub fn spot_power_per_intensity(inner: f64, outer: f64) -> f64 {
    let one_minus_inner = 2.0 * (0.5 * inner).sin().powi(2);
    let width = 2.0 * (0.5 * (outer + inner)).sin() * (0.5 * (outer - inner)).sin();
    std::f64::consts::TAU * (one_minus_inner + width / 3.0)
}

/// Checks the GLB container (header and chunk headers) before the `gltf` crate reads it,
/// so that every malformed file gets a message with its numbers.
fn check_glb(bytes: &[u8]) -> Result<(), SceneError> {
    let bad = |message: String| SceneError::Import {
        format: "glb",
        message,
    };
    let word = |at: usize| -> Option<u32> {
        bytes
            .get(at..at + 4)
            .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
    };
    if !bytes.starts_with(b"glTF") {
        return Err(bad(format!(
            "wrong magic {:?} (expected \"glTF\")",
            String::from_utf8_lossy(&bytes[..bytes.len().min(4)])
        )));
    }
    let (Some(version), Some(length)) = (word(4), word(8)) else {
        return Err(bad(format!(
            "truncated header: {} bytes, a GLB header has 12",
            bytes.len()
        )));
    };
    if version != 2 {
        return Err(bad(format!("version {version} (only glTF 2 is read)")));
    }
    if length as usize != bytes.len() {
        return Err(bad(format!(
            "the header's length {length} differs from the file's {} bytes",
            bytes.len()
        )));
    }
    let mut at = 12;
    let mut first = true;
    while at < bytes.len() {
        let (Some(chunk_length), Some(kind)) = (word(at), word(at + 4)) else {
            return Err(bad(format!("truncated chunk header at byte {at}")));
        };
        let end = (at + 8).checked_add(chunk_length as usize);
        if end.is_none_or(|end| end > bytes.len()) {
            return Err(bad(format!(
                "chunk at byte {at}: its length {chunk_length} runs past the file's end ({} bytes)",
                bytes.len()
            )));
        }
        if first && kind != 0x4E4F_534A {
            return Err(bad(format!(
                "the first chunk is not JSON (type 0x{kind:08x})"
            )));
        }
        first = false;
        at += 8 + chunk_length as usize;
    }
    if first {
        return Err(bad("no JSON chunk".to_owned()));
    }
    Ok(())
}

/// One way a node may be named in messages: `nodes[5] 'Lamp'`.
fn node_label(index: usize, name: Option<&str>) -> String {
    match name {
        Some(n) if !n.is_empty() => format!("nodes[{index}] '{n}'"),
        _ => format!("nodes[{index}]"),
    }
}

/// The node's local transform in `f64`.
fn local_matrix(node: &gltf::Node<'_>, label: &str) -> Result<DMat4, SceneError> {
    let f = |v: f32| f64::from(v);
    Ok(match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => {
            DMat4::from_cols_array_2d(&matrix.map(|c| c.map(f)))
        }
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let q = DQuat::from_array(rotation.map(f));
            let length = q.length();
            if !(length.is_finite() && length > 0.0) {
                return Err(SceneError::invalid(
                    format!("{label}.rotation"),
                    format!("not a rotation quaternion ({rotation:?})"),
                ));
            }
            DMat4::from_scale_rotation_translation(
                DVec3::from_array(scale.map(f)),
                q / length,
                DVec3::from_array(translation.map(f)),
            )
        }
    })
}

/// The document's nodes' parents, refusing a node with two parents and cycles.
fn parents(document: &gltf::Document) -> Result<Vec<Option<usize>>, SceneError> {
    let nodes: Vec<gltf::Node<'_>> = document.nodes().collect();
    let mut parent: Vec<Option<usize>> = vec![None; nodes.len()];
    for node in &nodes {
        for child in node.children() {
            let c = child.index();
            if let Some(p) = parent[c] {
                return Err(SceneError::invalid(
                    node_label(c, child.name()),
                    format!(
                        "has two parents (nodes[{p}] and nodes[{}]): a node belongs to one tree",
                        node.index()
                    ),
                ));
            }
            parent[c] = Some(node.index());
        }
    }
    // Follow each node's parents until a node already known to reach a root; a node met
    // twice on one walk closes a cycle. Every node is walked once: O(N).
    let mut state = vec![0u8; nodes.len()]; // 0 unseen, 1 on the current walk, 2 done
    let mut walk = Vec::new();
    for start in 0..nodes.len() {
        let mut at = Some(start);
        while let Some(v) = at {
            match state[v] {
                2 => break,
                1 => {
                    return Err(SceneError::invalid(
                        node_label(v, nodes[v].name()),
                        "is its own ancestor: the node graph has a cycle",
                    ));
                }
                _ => {
                    state[v] = 1;
                    walk.push(v);
                    at = parent[v];
                }
            }
        }
        for v in walk.drain(..) {
            state[v] = 2;
        }
    }
    Ok(parent)
}

/// Reads the lights of a glTF document (`.gltf` text or `.glb`) as a scene named `name`.
pub(super) fn read(
    bytes: &[u8],
    name: &str,
    format: SceneFormat,
) -> Result<(Scene, ImportReport), SceneError> {
    let gltf = parse(bytes, format)?;
    let document = &gltf.document;
    let parent = parents(document)?;
    let roots = scene_roots(document, &parent)?;
    let nodes: Vec<gltf::Node<'_>> = document.nodes().collect();
    // Each node has one parent and each root is listed once, so a light appears at most
    // once per node that references it: refuse too many before reading any.
    check_count(
        nodes.iter().filter(|n| n.light().is_some()).count(),
        "lights",
    )?;
    let mut positions = Vec::new();
    let mut powers = Vec::new();
    let mut shapes: Vec<(Option<Spot>, Option<f64>)> = Vec::new();
    let mut names: Vec<String> = Vec::new();
    let mut skipped = Vec::new();
    let mut stack: Vec<(usize, DMat4)> =
        roots.iter().rev().map(|&r| (r, DMat4::IDENTITY)).collect();
    while let Some((index, parent_world)) = stack.pop() {
        let node = &nodes[index];
        let label = node_label(index, node.name());
        let world = parent_world * local_matrix(node, &label)?;
        if !world.is_finite() {
            return Err(SceneError::invalid(
                format!("{label}.matrix"),
                "the world transform is not finite (NaN or overflow)",
            ));
        }
        let children: Vec<usize> = node.children().map(|c| c.index()).collect();
        stack.extend(children.into_iter().rev().map(|c| (c, world)));
        let Some(light) = node.light() else { continue };
        match read_light(node, &light, &label, &world)? {
            NodeLight::Skipped(skip) => skipped.push(skip),
            NodeLight::Read(l) => {
                positions.push(l.position);
                powers.push(l.power);
                shapes.push((l.spot, l.range));
                names.push(l.name);
            }
        }
    }
    if positions.is_empty() {
        return Err(SceneError::invalid(
            "KHR_lights_punctual",
            if skipped.is_empty() {
                "no point or spot light in the file's scene".to_owned()
            } else {
                format!(
                    "no point or spot light in the file's scene (skipped {} directional)",
                    skipped.len()
                )
            },
        ));
    }
    let plane = footprint_plane(&positions, IMPORT_PLANE_PIXELS);
    let mut scene = Scene::from_parts(name, plane, positions, powers).map_err(|e| match e {
        // Name the file's terms, not the scene file's.
        SceneError::AllZero { count, .. } => SceneError::AllZero {
            field: "KHR_lights_punctual".to_owned(),
            count,
        },
        other => other,
    })?;
    let extras = crate::scene::json::LightExtras {
        shapes,
        names: names
            .into_iter()
            .map(|n| (!n.is_empty()).then_some(n))
            .collect(),
    };
    extras.attach(&mut scene, "lights")?;
    let mut report = ImportReport::of(&scene, format);
    report.skipped = skipped;
    Ok((scene, report))
}

/// Parses the document (a `.glb`'s header checked first); a validation error names the
/// first problem's path and how many more there are.
fn parse(bytes: &[u8], format: SceneFormat) -> Result<gltf::Gltf, SceneError> {
    let fmt = format.name();
    if format == SceneFormat::Glb {
        check_glb(bytes)?;
    }
    gltf::Gltf::from_slice(bytes).map_err(|e| SceneError::Import {
        format: fmt,
        message: match e {
            gltf::Error::Validation(errors) => {
                let (path, error) = &errors[0];
                let more = errors.len() - 1;
                format!(
                    "invalid glTF: {path}: {error}{}",
                    if more > 0 {
                        format!(" (and {more} more)")
                    } else {
                        String::new()
                    }
                )
            }
            other => other.to_string(),
        },
    })
}

/// The root nodes of the document's scene (the default one, else the first; without
/// scenes, every node without a parent), each listed once and none a child.
fn scene_roots(
    document: &gltf::Document,
    parent: &[Option<usize>],
) -> Result<Vec<usize>, SceneError> {
    let roots: Vec<usize> = match document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        Some(scene) => scene.nodes().map(|n| n.index()).collect(),
        None => (0..parent.len()).filter(|&i| parent[i].is_none()).collect(),
    };
    let mut listed = vec![false; parent.len()];
    for &r in &roots {
        if std::mem::replace(&mut listed[r], true) {
            return Err(SceneError::invalid(
                node_label(r, document.nodes().nth(r).and_then(|n| n.name())),
                "is listed twice among the scene's root nodes",
            ));
        }
        if let Some(p) = parent[r] {
            return Err(SceneError::invalid(
                node_label(r, document.nodes().nth(r).and_then(|n| n.name())),
                format!("is a scene root but also a child of nodes[{p}]"),
            ));
        }
    }
    Ok(roots)
}

/// What a node's light becomes: a point or spot light of the scene, or a skipped light.
enum NodeLight {
    Read(ReadLight),
    Skipped(SkippedLight),
}

/// A point or spot light as read: in lightpick's axes, its power from its intensity and
/// colour, its cone and range as given, and its display name (empty for none).
struct ReadLight {
    position: DVec3,
    power: f64,
    spot: Option<Spot>,
    range: Option<f64>,
    name: String,
}

/// Reads `light`, referenced by `node` (`label`) with world transform `world`: a
/// directional light is skipped; a point or spot light's intensity, colour, cone and range
/// are checked (errors name `label → KHR_lights_punctual.lights[i].field`).
fn read_light(
    node: &gltf::Node<'_>,
    light: &gltf::khr_lights_punctual::Light<'_>,
    label: &str,
    world: &DMat4,
) -> Result<NodeLight, SceneError> {
    let light_label = match light.name() {
        Some(n) if !n.is_empty() => format!("lights[{}] '{n}'", light.index()),
        _ => format!("lights[{}]", light.index()),
    };
    let field = |what: &str| format!("{label} → KHR_lights_punctual.{light_label}.{what}");
    let display_name = node
        .name()
        .filter(|n| !n.is_empty())
        .or(light.name())
        .unwrap_or("")
        .to_owned();
    let spot = match light.kind() {
        gltf::khr_lights_punctual::Kind::Directional => {
            return Ok(NodeLight::Skipped(SkippedLight {
                name: if display_name.is_empty() {
                    label.to_owned()
                } else {
                    display_name
                },
                reason: "directional light (at infinity, not a point light)".to_owned(),
            }));
        }
        gltf::khr_lights_punctual::Kind::Point => None,
        gltf::khr_lights_punctual::Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => Some(spot_cone(inner_cone_angle, outer_cone_angle, world)),
    };
    let intensity = f64::from(light.intensity());
    if !intensity.is_finite() {
        return Err(SceneError::NotFinite {
            field: field("intensity"),
            value: intensity,
        });
    }
    if intensity < 0.0 {
        return Err(SceneError::Negative {
            field: field("intensity"),
            value: intensity,
        });
    }
    let color = light.color().map(f64::from);
    if let Some(c) = color.iter().position(|c| !c.is_finite() || *c < 0.0) {
        return Err(SceneError::invalid(
            field(&format!("color[{c}]")),
            format!("must be finite and non-negative (got {})", color[c]),
        ));
    }
    let range = light.range().map(f64::from);
    let emission = Emission::new(spot, range).map_err(|e| {
        let what = match e.field() {
            "spot" => "spot",
            "spot.direction" => "spot (its node's world axis)",
            _ => "range",
        };
        SceneError::invalid(field(what), e.to_string())
    })?;
    let per_intensity = match emission.spot() {
        Some(s) => spot_power_per_intensity(s.inner_cone, s.outer_cone),
        None => 2.0 * std::f64::consts::TAU,
    };
    Ok(NodeLight::Read(ReadLight {
        position: to_lightpick(world.transform_point3(DVec3::ZERO)),
        power: per_intensity * intensity * luminance(color),
        spot,
        range,
        name: display_name,
    }))
}

/// A glTF spot's cone in lightpick's terms: its axis (the node's world `−Z`, normalized)
/// and its half-angles, an `f32` π/2 taken as the hemisphere.
fn spot_cone(inner_cone_angle: f32, outer_cone_angle: f32, world: &DMat4) -> Spot {
    let (inner, mut outer) = (f64::from(inner_cone_angle), f64::from(outer_cone_angle));
    // π/2 written in f32 rounds up past π/2: that is the hemisphere.
    if outer > std::f64::consts::FRAC_PI_2 && outer <= f64::from(std::f32::consts::FRAC_PI_2) {
        outer = std::f64::consts::FRAC_PI_2;
    }
    let axis = to_lightpick(world.transform_vector3(DVec3::NEG_Z));
    let axis = axis.try_normalize().unwrap_or(axis);
    Spot {
        direction: axis,
        inner_cone: inner,
        outer_cone: outer,
    }
}
