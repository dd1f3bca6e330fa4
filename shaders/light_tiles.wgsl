// Screen tiles of light indices, written by the light culling pass and read by the
// lighting pass. Per tile: the number of point lights, the number of spot lights, then up
// to MAX_TILE_LIGHTS point-light indices and up to MAX_TILE_LIGHTS spot-light indices.
// A count of TILE_OVERFLOW means more lights reach the tile than it holds: the lighting
// pass then loops over every light of that kind (slower, never wrong).

const TILE_SIZE: u32 = 16u;
const MAX_TILE_LIGHTS: u32 = 255u;
const TILE_STRIDE: u32 = 2u + 2u * MAX_TILE_LIGHTS;
const TILE_OVERFLOW: u32 = 0xffffffffu;

// Index of the first word of the tile holding `pixel`, for a target `width` pixels wide.
fn tile_base(pixel: vec2<u32>, width: u32) -> u32 {
    let tiles_x = (width + TILE_SIZE - 1u) / TILE_SIZE;
    let tile = pixel / TILE_SIZE;
    return (tile.y * tiles_x + tile.x) * TILE_STRIDE;
}
