// Converts an OBJ + MTL scene (the bundled data/cornell_box.obj) into a glTF 2.0 file with
// its buffer embedded, so that three.js's GLTFLoader shows the scene that vdblight baked:
// the same coordinates (no transform: both are Y-up and the OBJ is in metres), one node per
// OBJ object, flat face normals, Kd as base colour (metallic 0, roughness 1) and Ke
// (emitted radiance) as emissive colour with KHR_materials_emissive_strength above 1.
//
//   node examples/web/tools/obj_to_gltf.mjs data/cornell_box.obj out/scene.gltf
//
// Only what vdblight's bundled scenes use: v, f (polygons, fanned into triangles; v, v/vt,
// v//vn and v/vt/vn indices, negative ones too), o / g, usemtl, mtllib with Kd and Ke.
import { readFileSync, writeFileSync, renameSync } from 'node:fs';
import { dirname, join, basename } from 'node:path';

function parseMtl(text) {
	const materials = new Map();
	let current = null;
	for (const raw of text.split('\n')) {
		const [key, ...rest] = raw.trim().split(/\s+/);
		if (key === 'newmtl') materials.set(rest[0], current = { kd: [0.8, 0.8, 0.8], ke: [0, 0, 0] });
		else if (current && (key === 'Kd' || key === 'Ke')) current[key.toLowerCase()] = rest.slice(0, 3).map(Number);
	}
	return materials;
}

function parseObj(text, objDir) {
	const positions = [];
	const objects = [];  // { name, groups: Map(material -> [triangle vertex positions]) }
	let materials = new Map();
	let object = null, material = '';
	const currentObject = () => object ??= (objects.push({ name: 'object', groups: new Map() }), objects.at(-1));
	for (const raw of text.split('\n')) {
		const [key, ...rest] = raw.trim().split(/\s+/);
		if (key === 'v') positions.push(rest.slice(0, 3).map(Number));
		else if (key === 'o' || key === 'g') { objects.push({ name: rest.join(' ') || 'object', groups: new Map() }); object = objects.at(-1); }
		else if (key === 'usemtl') material = rest[0];
		else if (key === 'mtllib') materials = parseMtl(readFileSync(join(objDir, rest.join(' ')), 'utf8'));
		else if (key === 'f') {
			const idx = rest.map(t => { const i = parseInt(t.split('/')[0], 10); return i < 0 ? positions.length + i : i - 1; });
			if (idx.some(i => !(i >= 0 && i < positions.length))) throw new Error(`face index out of range: ${raw}`);
			const groups = currentObject().groups;
			if (!groups.has(material)) groups.set(material, []);
			const tris = groups.get(material);
			for (let k = 1; k + 1 < idx.length; ++k) tris.push(positions[idx[0]], positions[idx[k]], positions[idx[k + 1]]);
		}
	}
	return { objects: objects.filter(o => o.groups.size > 0), materials };
}

// The face normal of a triangle, (p1 - p0) x (p2 - p0) normalised (counter-clockwise front).
function faceNormal(a, b, c) {
	const u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]], v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
	const n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
	const l = Math.hypot(...n) || 1;
	return n.map(x => x / l);
}

function toGltf({ objects, materials }, name) {
	const gltf = { asset: { version: '2.0', generator: 'vdblight examples/web/tools/obj_to_gltf.mjs' },
		scene: 0, scenes: [{ name, nodes: [] }], nodes: [], meshes: [], materials: [], accessors: [], bufferViews: [], buffers: [] };
	const chunks = [];
	let byteLength = 0;
	const materialIndex = new Map();
	const addView = (floats, target) => {
		const bytes = Buffer.from(new Float32Array(floats).buffer);
		gltf.bufferViews.push({ buffer: 0, byteOffset: byteLength, byteLength: bytes.length, target });
		chunks.push(bytes);
		byteLength += bytes.length;
		return gltf.bufferViews.length - 1;
	};
	const materialOf = (mtl) => {
		if (materialIndex.has(mtl)) return materialIndex.get(mtl);
		const m = materials.get(mtl) ?? { kd: [0.8, 0.8, 0.8], ke: [0, 0, 0] };
		const out = { name: mtl || 'default', pbrMetallicRoughness: { baseColorFactor: [...m.kd, 1], metallicFactor: 0, roughnessFactor: 1 } };
		const strength = Math.max(...m.ke);
		if (strength > 0) {
			out.emissiveFactor = m.ke.map(x => x / Math.max(1, strength));
			if (strength > 1) {
				out.extensions = { KHR_materials_emissive_strength: { emissiveStrength: strength } };
				gltf.extensionsUsed = ['KHR_materials_emissive_strength'];
			}
		}
		gltf.materials.push(out);
		materialIndex.set(mtl, gltf.materials.length - 1);
		return gltf.materials.length - 1;
	};
	for (const object of objects) {
		const primitives = [];
		for (const [mtl, vertices] of object.groups) {
			const pos = [], nrm = [];
			for (let t = 0; t < vertices.length; t += 3) {
				const n = faceNormal(vertices[t], vertices[t + 1], vertices[t + 2]);
				for (let k = 0; k < 3; ++k) { pos.push(...vertices[t + k]); nrm.push(...n); }
			}
			const min = [0, 1, 2].map(a => Math.min(...vertices.map(v => v[a])));
			const max = [0, 1, 2].map(a => Math.max(...vertices.map(v => v[a])));
			gltf.accessors.push({ bufferView: addView(pos, 34962), componentType: 5126, count: vertices.length, type: 'VEC3',
				min: min.map(Math.fround), max: max.map(Math.fround) });  // as the float32 data holds them
			gltf.accessors.push({ bufferView: addView(nrm, 34962), componentType: 5126, count: vertices.length, type: 'VEC3' });
			const a = gltf.accessors.length;
			primitives.push({ attributes: { POSITION: a - 2, NORMAL: a - 1 }, material: materialOf(mtl) });
		}
		gltf.meshes.push({ name: object.name, primitives });
		gltf.nodes.push({ name: object.name, mesh: gltf.meshes.length - 1 });
		gltf.scenes[0].nodes.push(gltf.nodes.length - 1);
	}
	gltf.buffers.push({ byteLength, uri: 'data:application/octet-stream;base64,' + Buffer.concat(chunks).toString('base64') });
	return gltf;
}

const [input, output] = process.argv.slice(2);
if (!input || !output) {
	console.error('usage: node obj_to_gltf.mjs SCENE.obj OUT.gltf');
	process.exit(2);
}
try {
	const scene = parseObj(readFileSync(input, 'utf8'), dirname(input));
	if (scene.objects.length === 0) throw new Error(`no faces in ${input}`);
	const text = JSON.stringify(toGltf(scene, basename(input)));
	const temporary = `${output}.tmp-${process.pid}`;  // renamed into place: never a half-written file
	writeFileSync(temporary, text);
	renameSync(temporary, output);
} catch (e) {
	console.error(`obj_to_gltf: ${e.message}`);
	process.exit(1);
}
