//! glTF skins and morph targets: a primitive's `JOINTS_0`/`WEIGHTS_0` and morph targets
//! (position, normal and tangent offsets), and a node's skin (its joints and inverse bind
//! matrices), as [`crate::scene::deform`] uses them. Every accessor is checked against
//! its buffer before it is read.

use super::gltf_buffers::check_accessor;
use super::gltf_quantized::read_attribute;
use crate::scene::{MorphTarget, SkinnedMesh};
use bevy_ecs::prelude::Entity;
use glam::Mat4;
use std::collections::HashMap;

/// A primitive's per-vertex joints and weights (both empty without a skin) and morph
/// targets.
pub(super) struct PrimitiveDeformation {
    pub joints: Vec<[u32; 4]>,
    pub weights: Vec<[f32; 4]>,
    pub targets: Vec<MorphTarget>,
}

/// The deformation data of `primitive` (`None` when it has neither joints nor morph
/// targets). A second joint set (`JOINTS_1`, more than four influences) is left out with
/// a warning.
pub(super) fn read_deformation(
    primitive: &gltf::Primitive,
    buffers: &[gltf::buffer::Data],
    warnings: &mut Vec<String>,
    what: &str,
) -> Result<Option<PrimitiveDeformation>, String> {
    for (semantic, accessor) in primitive.attributes() {
        if matches!(
            semantic,
            gltf::Semantic::Joints(_) | gltf::Semantic::Weights(_)
        ) {
            check_accessor(&accessor, buffers)?;
        }
        if matches!(semantic, gltf::Semantic::Joints(1..)) {
            warnings.push(format!(
                "{what}: {semantic:?} is not used (at most 4 joints per vertex)"
            ));
        }
    }
    for target in primitive.morph_targets() {
        for accessor in [target.positions(), target.normals(), target.tangents()]
            .into_iter()
            .flatten()
        {
            check_accessor(&accessor, buffers)?;
        }
    }
    let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
    let joints: Vec<[u32; 4]> = reader
        .read_joints(0)
        .map(|j| j.into_u16().map(|j| j.map(u32::from)).collect())
        .unwrap_or_default();
    let weights: Vec<[f32; 4]> = reader
        .read_weights(0)
        .map(|w| w.into_f32().collect())
        .unwrap_or_default();
    let (joints, weights) = if joints.is_empty() != weights.is_empty() {
        warnings.push(format!(
            "{what}: JOINTS_0 without WEIGHTS_0 (or the reverse): not skinned"
        ));
        (Vec::new(), Vec::new())
    } else {
        (joints, weights)
    };
    // Each target's offsets through the glTF reader when they are f32, dequantized
    // (KHR_mesh_quantization) otherwise.
    let mut targets = Vec::new();
    for (target, (p, n, t)) in primitive.morph_targets().zip(reader.read_morph_targets()) {
        let read = |a: Option<gltf::Accessor>, floats: Option<Vec<[f32; 3]>>| match a {
            Some(a) => read_attribute(&a, buffers, || floats).map(Option::unwrap_or_default),
            None => Ok(Vec::new()),
        };
        targets.push(MorphTarget {
            positions: read(target.positions(), p.map(Iterator::collect))?,
            normals: read(target.normals(), n.map(Iterator::collect))?,
            tangents: read(target.tangents(), t.map(Iterator::collect))?,
        });
    }
    if joints.is_empty() && targets.is_empty() {
        return Ok(None);
    }
    Ok(Some(PrimitiveDeformation {
        joints,
        weights,
        targets,
    }))
}

/// The [`SkinnedMesh`] of `skin`: its joints' entities (through `nodes`, glTF node index
/// → entity) and inverse bind matrices (identity where the file gives none). Fails on a
/// joint outside the loaded scene or a matrix that is missing or not finite.
pub(super) fn read_skin(
    skin: &gltf::Skin,
    buffers: &[gltf::buffer::Data],
    nodes: &HashMap<usize, Entity>,
) -> Result<SkinnedMesh, String> {
    let joints = skin
        .joints()
        .map(|j| {
            nodes.get(&j.index()).copied().ok_or(format!(
                "joint node {} is not in the loaded scene",
                j.index()
            ))
        })
        .collect::<Result<Vec<_>, _>>()?;
    if let Some(accessor) = skin.inverse_bind_matrices() {
        check_accessor(&accessor, buffers)?;
    }
    let reader = skin.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
    let inverse_bind: Vec<Mat4> = match reader.read_inverse_bind_matrices() {
        Some(m) => m.map(|m| Mat4::from_cols_array_2d(&m)).collect(),
        None => vec![Mat4::IDENTITY; joints.len()],
    };
    if inverse_bind.len() < joints.len() {
        return Err(format!(
            "{} inverse bind matrices for {} joints",
            inverse_bind.len(),
            joints.len()
        ));
    }
    if inverse_bind.iter().any(|m| !m.is_finite()) {
        return Err("an inverse bind matrix is not finite".into());
    }
    Ok(SkinnedMesh {
        inverse_bind: inverse_bind[..joints.len()].into(),
        joints,
    })
}
