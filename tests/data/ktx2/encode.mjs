import { encodeToKTX2 } from "ktx2-encoder";
import fs from "fs";
const jobs = [];
// 8 × 8 quadrants: red, green / blue, white; and a 4 × 4 orange (sRGB bytes).
const quad = new Uint8Array(8 * 8 * 4);
const colours = [[230, 40, 30], [40, 200, 60], [30, 60, 220], [240, 240, 240]];
for (let y = 0; y < 8; y++) for (let x = 0; x < 8; x++) {
  quad.set([...colours[(y < 4 ? 0 : 2) + (x < 4 ? 0 : 1)], 255], (y * 8 + x) * 4);
}
const orange = new Uint8Array(4 * 4 * 4);
for (let i = 0; i < 16; i++) orange.set([230, 120, 30, 255], i * 4);
for (const [name, data, size] of [["quadrants", quad, 8], ["orange", orange, 4]]) {
  for (const [suffix, uastc] of [["etc1s", false], ["uastc_zstd", true]]) {
    const out = await encodeToKTX2(new Uint8Array(4), {
      isUASTC: uastc, needSupercompression: uastc, generateMipmap: false,
      isSetKTX2SRGBTransferFunc: true, qualityLevel: 255,
      imageDecoder: async () => ({ data, width: size, height: size }),
    });
    fs.writeFileSync(`${name}_${suffix}.ktx2`, out);
  }
}
