// A glTF 2.0 binary read in Node without three.js (glTF 2.0 specification, "GLB File Format
// Specification" and "Accessors"), for the test to know what `export --format gltf` wrote
// independently of the GLTFLoader that the page uses.
import { readFileSync } from 'node:fs';

const componentArrays = { 5126: Float32Array, 5125: Uint32Array, 5123: Uint16Array, 5121: Uint8Array };
const componentsPerType = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4 };

/** { json, accessor(i) }: the JSON chunk, and accessor i's values as a typed array (tightly packed views only). */
export function readGlb(path) {
	const bytes = readFileSync(path);
	if (bytes.length < 20 || bytes.toString('latin1', 0, 4) !== 'glTF' || bytes.readUInt32LE(4) !== 2)
		throw new Error(`${path}: not a glTF 2.0 binary`);
	if (bytes.readUInt32LE(8) !== bytes.length) throw new Error(`${path}: header length ${bytes.readUInt32LE(8)}, file ${bytes.length}`);
	const jsonLength = bytes.readUInt32LE(12);
	if (bytes.toString('latin1', 16, 20) !== 'JSON') throw new Error(`${path}: first chunk is not JSON`);
	const json = JSON.parse(bytes.toString('utf8', 20, 20 + jsonLength));
	const binHeader = 20 + jsonLength;
	if (bytes.toString('latin1', binHeader + 4, binHeader + 8) !== 'BIN\0') throw new Error(`${path}: no BIN chunk`);
	const bin = bytes.subarray(binHeader + 8, binHeader + 8 + bytes.readUInt32LE(binHeader));
	const accessor = (i) => {
		const a = json.accessors[i], view = json.bufferViews[a.bufferView];
		const Type = componentArrays[a.componentType];
		if (!Type || view.byteStride) throw new Error(`${path}: accessor ${i} is not a packed array this reader handles`);
		const start = (view.byteOffset ?? 0) + (a.byteOffset ?? 0), count = a.count * componentsPerType[a.type];
		if (start + count * Type.BYTES_PER_ELEMENT > bin.length) throw new Error(`${path}: accessor ${i} runs past the BIN chunk`);
		return new Type(bin.buffer.slice(bin.byteOffset + start, bin.byteOffset + start + count * Type.BYTES_PER_ELEMENT));
	};
	return { json, accessor };
}
