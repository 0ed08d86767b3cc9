// Fills three.js's LightProbeGridWebGL (r187) from `vdblight export --format three` instead
// of baking it in the browser: probe_grid.json places and sizes the grid, probe_grid_sh.bin
// is its SH atlas texture as the class lays it out (docs/engines.md, "three.js").
//
//   import { loadProbeGrid } from './vdblight-loader.js';
//   const grid = await loadProbeGrid('data/');   // a LightProbeGridWebGL
//   scene.add(grid);                             // lights every lit material inside its box
import { Data3DTexture, FloatType, HalfFloatType, LinearFilter, RGBAFormat } from 'three';
import { LightProbeGridWebGL } from 'three/addons/lighting/LightProbeGridWebGL.js';

const FORMAT = 'vdblight-three-light-probe-grid';

/** The atlas as a Data3DTexture of the type and size that `info.texture` states. */
export function atlasTexture(info, buffer) {
	const t = info.texture;
	const half = t.type === 'float16';
	if (!half && t.type !== 'float32') throw new Error(`vdblight: unknown texel type '${t.type}'`);
	if (buffer.byteLength !== t.byte_length || t.byte_length !== t.width * t.height * t.depth * (half ? 8 : 16))
		throw new Error(`vdblight: ${t.file} holds ${buffer.byteLength} bytes, expected ${t.byte_length}`);
	const data = half ? new Uint16Array(buffer) : new Float32Array(buffer);
	const texture = new Data3DTexture(data, t.width, t.height, t.depth);
	texture.format = RGBAFormat;
	texture.type = half ? HalfFloatType : FloatType;
	texture.minFilter = texture.magFilter = LinearFilter;  // the class's trilinear interpolation between probes
	texture.generateMipmaps = false;
	texture.unpackAlignment = 1;
	texture.needsUpdate = true;
	return texture;
}

/** Places an existing grid over the volume and gives it the baked atlas. */
export function fillProbeGrid(grid, info, buffer) {
	if (info.format !== FORMAT || info.version !== 1) throw new Error(`vdblight: not a version-1 ${FORMAT} file`);
	const [nx, ny, nz] = info.resolution;
	if (info.texture.width !== nx || info.texture.height !== ny || info.texture.depth !== 7 * (nz + 2))
		throw new Error('vdblight: the atlas does not match the grid resolution');
	grid.resolution.set(nx, ny, nz);
	[grid.width, grid.height, grid.depth] = info.size;
	grid.position.set(...info.center);
	grid.updateBoundingBox();  // the shader reads boundingBox; only bake() would update it otherwise
	if (grid.texture && grid.texture.isData3DTexture) grid.texture.dispose();
	grid.texture = atlasTexture(info, buffer);
	return grid;
}

/** Fetches probe_grid.json and its atlas under `baseUrl` and returns a filled grid and the JSON. */
export async function loadProbeGrid(baseUrl, grid = null) {
	const base = new URL(baseUrl, document.baseURI);
	const fetchOk = async (url) => {
		const r = await fetch(url);
		if (!r.ok) throw new Error(`vdblight: ${url}: HTTP ${r.status}`);
		return r;
	};
	const info = await (await fetchOk(new URL('probe_grid.json', base))).json();
	const buffer = await (await fetchOk(new URL(info.texture.file, base))).arrayBuffer();
	const target = grid ?? new LightProbeGridWebGL(...info.size, ...info.resolution);
	fillProbeGrid(target, info, buffer);
	target.userData.vdblight = info;
	return target;
}
