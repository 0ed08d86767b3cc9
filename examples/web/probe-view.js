// The glTF probe view that `vdblight export --format gltf` writes (probes.glb, docs/engines.md
// "glTF probe view"), loaded with three's own GLTFLoader: one small sphere per chosen node,
// each vertex coloured by the irradiance for its normal (KHR_materials_unlit, so three draws
// the stored linear colours as they are), and the volume's box as lines.
//
//   import { loadProbeView } from './probe-view.js';
//   const view = await loadProbeView('data/probes.glb');   // view.root starts hidden
//   scene.add(view.root); view.root.visible = true;          // view.spheres: spheres loaded
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

/**
 * The number of connected parts of an indexed triangle mesh: vertices joined by a triangle
 * are one part (union-find). The export's spheres share no vertex, so this counts the
 * spheres that arrived in the geometry three built, without trusting the file's own count.
 */
export function countConnectedParts(geometry) {
	const index = geometry.index ? geometry.index.array : null;
	if (!index) throw new Error('vdblight: the probe mesh has no index buffer');
	const parent = new Int32Array(geometry.attributes.position.count).map((_, i) => i);
	const find = (v) => {
		while (parent[v] !== v) v = parent[v] = parent[parent[v]];  // path halving
		return v;
	};
	for (let t = 0; t + 2 < index.length; t += 3) {
		const a = find(index[t]);
		for (const v of [index[t + 1], index[t + 2]]) {
			const b = find(v);
			if (b !== a) parent[b] = a;
		}
	}
	const roots = new Set();
	for (let i = 0; i < index.length; ++i) roots.add(find(index[i]));
	return roots.size;
}

/** Loads probes.glb; resolves to { root (hidden), probes (the sphere mesh), box, spheres, colourScale }. */
export async function loadProbeView(url) {
	const gltf = await new GLTFLoader().loadAsync(url);
	let probes = null, box = null;
	gltf.scene.traverse((o) => {
		if (o.isMesh && o.geometry.attributes.color && !probes) probes = o;
		if (o.isLineSegments && !box) box = o;
	});
	if (!probes) throw new Error(`vdblight: ${url} has no mesh with vertex colours (not a vdblight probe view?)`);
	// Shown as glTF viewers show unlit colours: linear, encoded to sRGB, without the page's
	// tone mapping (which would darken them further; render targets never tone-map).
	probes.material.toneMapped = false;
	const info = gltf.scene.userData.vdblight ?? {};
	gltf.scene.visible = false;
	return { root: gltf.scene, probes, box, spheres: countConnectedParts(probes.geometry), colourScale: info.colour_scale ?? null };
}
