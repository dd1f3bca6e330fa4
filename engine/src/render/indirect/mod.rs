//! The passes of indirect light: what the frame adds to direct lighting so that light
//! arriving from other surfaces and from the environment is occluded and reflected.
//! Screen-space ambient occlusion ([`gtao`]), screen-space reflections
//! ([`reflections`]) over the [`depth_pyramid`], diffuse global illumination from the
//! probes of an irradiance volume ([`probe_volume`]) (looked up at half resolution by
//! [`volume_irradiance`]), and [`reflection_probes`]. The groups every pass that shades
//! surfaces binds for lights, shadows and indirect light are [`light_groups`].

pub mod capture;
pub mod depth_pyramid;
pub mod environment_maps;
pub mod gtao;
pub mod light_groups;
pub mod probe_volume;
pub mod reflection_probes;
pub mod reflections;
pub mod volume_irradiance;
