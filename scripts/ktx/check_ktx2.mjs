// Reads vdblight KTX2 exports with the npm package ktx-parse (pinned in package.json) and
// checks vkFormat and typeSize against each texture's manifest entry, size, depth and that
// write(read(file)) reproduces the file byte for byte, which catches alignment and padding
// errors that its reader does not check.
//
//   node scripts/ktx/check_ktx2.mjs EXPORT_DIR
// Exit status 0 when every texture of EXPORT_DIR/manifest.json passes.
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { read, write } from 'ktx-parse';

const dir = process.argv[2];
const manifest = JSON.parse(readFileSync(join(dir, 'manifest.json'), 'utf8'));
const [nx, ny, nz] = manifest.dims;
let failures = 0;
for (const tex of manifest.textures) {
  const bytes = new Uint8Array(readFileSync(join(dir, tex.file)));
  const c = read(bytes);
  const problems = [];
  if (c.vkFormat !== tex.vkFormat) problems.push(`vkFormat ${c.vkFormat}, manifest ${tex.vkFormat}`);
  // typeSize: bytes of one component (the four components of every exported format are equal).
  if (c.typeSize * 4 !== tex.bytes_per_texel) problems.push(`typeSize ${c.typeSize}`);
  if (c.pixelWidth !== nx || c.pixelHeight !== ny || c.pixelDepth !== nz)
    problems.push(`size ${c.pixelWidth} x ${c.pixelHeight} x ${c.pixelDepth}`);
  if (c.levels.length !== 1) problems.push(`${c.levels.length} levels`);
  if (c.keyValue.KTXorientation === undefined) problems.push('no KTXorientation');
  const again = write(c, { keepWriter: true });
  if (again.length !== bytes.length || !again.every((b, i) => b === bytes[i]))
    problems.push(`write(read(file)) differs (${again.length} vs ${bytes.length} bytes)`);
  if (problems.length) {
    failures++;
    console.log(`${tex.file}: ${problems.join('; ')}`);
  }
}
console.log(`ktx-parse: ${manifest.textures.length - failures} of ${manifest.textures.length} textures pass`);
process.exit(failures ? 1 : 0);
