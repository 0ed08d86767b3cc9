// The glTF probe view in the page (issue 31 item 4), checked by test/check_page.mjs on the
// page it has open:
//  1. the page loaded probes.glb with three's GLTFLoader, and the sphere mesh three built has as
//     many separate parts (spheres) as the export said it wrote and as the file's own count;
//  2. three draws the file's vertex colours: for every vertex of one sphere (the one whose
//     colours differ most, so that a constant or wrong colour cannot pass) the page renders the
//     loaded mesh looking at that vertex and the centre pixel, an RGBA8 value, must be the
//     vertex's COLOR_0 to 8-bit precision: |byte - 255 c| <= 0.5 (round to nearest) + 0.02 for
//     float interpolation, in each of r, g, b, and alpha 255 (the sphere, not the background).
import { readGlb } from './glb.mjs';

const TOLERANCE_BYTES = 0.52;

/** What the export wrote: the sphere mesh's vertices, grouped per sphere, and the file's count. */
function probeViewOf(path) {
	const { json, accessor } = readGlb(path);
	const mesh = json.meshes.find((m) => m.name === 'probes');
	if (!mesh) throw new Error(`${path}: no mesh named probes`);
	const attributes = mesh.primitives[0].attributes;
	const position = accessor(attributes.POSITION), normal = accessor(attributes.NORMAL), colour = accessor(attributes.COLOR_0);
	const spheres = json.scenes[json.scene ?? 0].extras.vdblight.spheres;
	const vertices = position.length / 3;
	if (!Number.isInteger(vertices / spheres)) throw new Error(`${path}: ${vertices} vertices do not split into ${spheres} spheres`);
	return { spheres, perSphere: vertices / spheres, position, normal, colour };
}

/** The sphere whose vertex colours span the widest range, and its vertices as render cases. */
function casesOfMostVariedSphere(view) {
	let best = 0, bestSpan = -1;
	for (let s = 0; s < view.spheres; ++s) {
		let lo = Infinity, hi = -Infinity;
		for (let v = s * view.perSphere; v < (s + 1) * view.perSphere; ++v)
			for (let a = 0; a < 3; ++a) { lo = Math.min(lo, view.colour[3 * v + a]); hi = Math.max(hi, view.colour[3 * v + a]); }
		if (hi - lo > bestSpan) { bestSpan = hi - lo; best = s; }
	}
	const first = best * view.perSphere, at = (v) => Array.from(view.position.slice(3 * v, 3 * v + 3));
	let diameter = 0;  // the sphere's vertices lie on it, the poles opposite: its radius from them
	for (let v = first; v < first + view.perSphere; ++v)
		for (let w = v + 1; w < first + view.perSphere; ++w) diameter = Math.max(diameter, Math.hypot(...at(v).map((x, a) => x - at(w)[a])));
	const radius = diameter / 2;
	const cases = [];
	for (let v = first; v < first + view.perSphere; ++v)
		cases.push({ position: at(v), normal: Array.from(view.normal.slice(3 * v, 3 * v + 3)),
			colour: Array.from(view.colour.slice(3 * v, 3 * v + 3)), halfWidth: 0.05 * radius, distance: 0.5 * radius });
	return { sphere: best, span: bestSpan, radius, cases };
}

/** Runs the checks on `page` (playwright); returns the problems found (empty: passed). */
export async function checkProbeView(page, glbPath, exportedSpheres) {
	const problems = [];
	const view = probeViewOf(glbPath);
	const loaded = await page.evaluate(() => {
		const v = window.vdblightPage.probeView;
		return v.error ? { error: v.error } : { spheres: v.spheres, vertices: v.probes.geometry.attributes.position.count };
	});
	if (loaded.error) return [`the page did not load probes.glb: ${loaded.error}`];
	console.log(`probe view: the page shows ${loaded.spheres} spheres (${loaded.vertices} vertices); ` +
		`the export wrote ${exportedSpheres}, probes.glb says ${view.spheres}`);
	if (loaded.spheres !== exportedSpheres || view.spheres !== exportedSpheres)
		problems.push(`sphere counts differ: page ${loaded.spheres}, export ${exportedSpheres}, file ${view.spheres}`);

	const { sphere, span, radius, cases } = casesOfMostVariedSphere(view);
	const pixels = await page.evaluate((cs) => {
		const p = window.vdblightPage;
		return p.readback.renderProbeVertices(p.renderer, p.probeView.probes, cs);
	}, cases);
	let worst = 0;
	cases.forEach((c, i) => {
		const px = pixels[i];
		const off = [0, 1, 2].map((a) => Math.abs(px[a] - 255 * c.colour[a]));
		worst = Math.max(worst, ...off);
		if (px[3] !== 255 || off.some((d) => !(d <= TOLERANCE_BYTES)))
			problems.push(`sphere ${sphere} vertex ${i}: pixel ${px} against COLOR_0 ${c.colour.map((x) => (255 * x).toFixed(2))} x 255`);
	});
	console.log(`probe view: sphere ${sphere} (radius ${radius.toPrecision(3)}, colours spanning ${span.toFixed(3)}), ` +
		`${cases.length} vertices read back: max |byte - 255 COLOR_0| = ${worst.toFixed(3)} (tolerance ${TOLERANCE_BYTES})`);
	return problems;
}
