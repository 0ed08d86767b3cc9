// The page in headless Chromium against `vdblight query` (run by tests/web_page_test.sh).
//
//   node check_page.mjs --data DIR --volume V.vdb --cli VDBLIGHT --screenshot OUT.png --probe-spheres N
//
// DIR holds `vdblight export V.vdb --format three`, scene.gltf and `export --format gltf`'s
// probes.glb, of which the export said it wrote N spheres (test/check_probe_view.mjs checks the
// page's probe view: the spheres it loaded and the colours it draws). The page is served on
// loopback and opened with ?test; Chromium (Debian's, software WebGL 2) then reads back the
// irradiance three.js computes from the grid in two ways:
//  1. its own GLSL (getLightProbeGridIrradiance of three's chunk) at random points and normals;
//  2. whole renders: white Lambert squares lit only by the grid, pixel * pi at each pixel's
//     centre (the material path: fragment position and normal, the grid's box test, the BRDF).
// Each is compared with `vdblight query --sh-order 2` at the point three.js samples, the
// fragment moved half a probe spacing along the normal. Tolerance, per point and channel:
// the atlas stores each coefficient rounded to half (relative error <= 2^-11) or float
// (2^-24), and E is a sum of coefficients times trilinear weights times |A_l Y_j(n)|, so
//   |E_three - E_query| <= u * S,  S = sum_j |A_l Y_j(n)| max over the 8 corner probes |c_j|
// plus float32 arithmetic on both sides (8 * 2^-24 * S) and 1e-6 W/m^2 for subnormal halves.
// Exits non-zero on any point beyond it; writes the page's screenshot (PNG), and OUT_probes.png
// with the probe view shown.
import { readFileSync, writeFileSync, mkdtempSync, rmSync, mkdirSync } from 'node:fs';
import { execFileSync } from 'node:child_process';
import { join, dirname } from 'node:path';
import { tmpdir } from 'node:os';
import { chromium } from 'playwright-core';
import { startServer } from '../serve.mjs';
import { checkProbeView } from './check_probe_view.mjs';

const args = process.argv.slice(2);
const option = (name) => { const i = args.indexOf(name); if (i < 0) throw new Error(`missing ${name}`); return args[i + 1]; };
const dataDir = option('--data'), volume = option('--volume'), cli = option('--cli'), screenshot = option('--screenshot');
const probeSpheres = Number(option('--probe-spheres'));

// --- the exported grid, read back in double: the corner magnitudes for the bound ------------
const info = JSON.parse(readFileSync(join(dataDir, 'probe_grid.json'), 'utf8'));
const half = info.texture.type === 'float16';
const bytes = readFileSync(join(dataDir, info.texture.file));
function halfToFloat(h) {
	const e = (h >> 10) & 31, m = h & 1023, s = h & 0x8000 ? -1 : 1;
	if (e === 0) return s * m * 2 ** -24;
	if (e === 31) return m ? NaN : s * Infinity;
	return s * (1 + m / 1024) * 2 ** (e - 15);
}
const atlas = new Float64Array(bytes.length / (half ? 2 : 4));
for (let i = 0; i < atlas.length; ++i) atlas[i] = half ? halfToFloat(bytes.readUInt16LE(2 * i)) : bytes.readFloatLE(4 * i);
const [NX, NY, NZ] = info.resolution;
const coefficient = (i, j, k, c) => {  // coefficient c (0..26: c0.r c0.g c0.b c1.r ...) of probe (i, j, k)
	const t = Math.floor(c / 4), slice = t * (NZ + 2) + 1 + k;
	return atlas[4 * ((slice * NY + j) * NX + i) + (c % 4)];
};
const A = [Math.PI, 2 * Math.PI / 3, 2 * Math.PI / 3, 2 * Math.PI / 3, Math.PI / 4, Math.PI / 4, Math.PI / 4, Math.PI / 4, Math.PI / 4];
const Y = ([x, y, z]) => [0.282095, 0.488603 * y, 0.488603 * z, 0.488603 * x, 1.092548 * x * y, 1.092548 * y * z,
	0.315392 * (3 * z * z - 1), 1.092548 * x * z, 0.546274 * (x * x - y * y)];
const unitRoundoff = half ? 2 ** -11 : 2 ** -24;
function bound(q, n) {
	const corners = [0, 1, 2].map((a) => {
		const t = Math.min(Math.max((q[a] - info.probe_min[a]) / info.probe_spacing[a], 0), info.resolution[a] - 1);
		const i0 = Math.min(Math.floor(t), info.resolution[a] - 2);
		return [i0, i0 + 1];
	});
	const y = Y(n);
	return [0, 1, 2].map((ch) => {
		let s = 0;
		for (let j = 0; j < 9; ++j) {
			let m = 0;
			for (const i of corners[0]) for (const jj of corners[1]) for (const k of corners[2])
				m = Math.max(m, Math.abs(coefficient(i, jj, k, 3 * j + ch)));
			s += Math.abs(A[j] * y[j]) * m;
		}
		return (unitRoundoff + 8 * 2 ** -24) * s + 1e-6;
	});
}

// --- the points: random in the probe box, random unit normals (fixed seed) ------------------
let seed = 12345;
const random = () => ((seed = (Math.imul(seed, 1664525) + 1013904223) >>> 0) / 2 ** 32);
function randomNormal() {
	const z = 2 * random() - 1, phi = 2 * Math.PI * random(), r = Math.sqrt(1 - z * z);
	return [r * Math.cos(phi), r * Math.sin(phi), z];
}
const glslPoints = [];
for (let i = 0; i < 256; ++i)
	glslPoints.push([[0, 1, 2].map((a) => info.probe_min[a] + random() * (info.probe_max[a] - info.probe_min[a])), randomNormal()]);
const centre = [0, 1, 2].map((a) => (info.probe_min[a] + info.probe_max[a]) / 2);
const extent = Math.min(...[0, 1, 2].map((a) => info.probe_max[a] - info.probe_min[a]));
const squares = [[0, 1, 0], [-1, 0, 0], [0, 0, -1], [0.48, 0.6, -0.64]].map((normal, i) => ({
	center: centre.map((c, a) => c + (a === i % 3 ? 0.1 : -0.05) * extent), normal, size: 0.6 * extent, pixels: 12,
}));

// --- the page in Chromium ---------------------------------------------------------------------
const flags = ['--no-sandbox', '--disable-quic', '--no-first-run', '--disable-background-networking',
	'--disable-component-update', '--disable-sync', '--enable-unsafe-swiftshader'];
const profile = mkdtempSync(join(tmpdir(), 'vdblight-chromium-'));
const started = Date.now();
const stage = (what) => console.log(`  ${what}: ${((Date.now() - started) / 1000).toFixed(1)} s`);
const { server, url } = await startServer({ dataDir });
let browser = null, failed = false;
try {
	browser = await chromium.launchPersistentContext(profile, {
		executablePath: process.env.VDBLIGHT_CHROMIUM ?? '/usr/bin/chromium', headless: true, args: flags,
		viewport: { width: 960, height: 600 },
	});
	const page = browser.pages()[0] ?? await browser.newPage();
	const consoleErrors = [];
	page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
	page.on('pageerror', (e) => consoleErrors.push(String(e)));
	await page.goto(`${url}?test&t=2.2`);
	await page.waitForFunction(() => window.vdblightPage && (window.vdblightPage.error || window.vdblightPage.frames >= 3),
		null, { timeout: 20000 });
	stage('page ready');
	const pageError = await page.evaluate(() => window.vdblightPage.error);
	if (pageError) throw new Error(`the page failed: ${pageError}`);
	const gl = await page.evaluate(() => { const g = window.vdblightPage.renderer.getContext(); return `${g.getParameter(g.VERSION)} | ${g.getParameter(g.RENDERER)}`; });
	console.log(`page: ${url}  (${gl})`);
	mkdirSync(dirname(screenshot), { recursive: true });
	writeFileSync(screenshot, await page.screenshot());
	console.log(`screenshot: ${screenshot}`);
	stage('screenshot');

	const glsl = await page.evaluate((pts) => {
		const p = window.vdblightPage;
		return p.readback.evaluateGrid(p.renderer, p.grid, pts.flat(2));
	}, glslPoints);
	const rendered = await page.evaluate((sq) => {
		const p = window.vdblightPage;
		return sq.map((s) => p.readback.renderSquare(p.renderer, p.grid, s)).flat();
	}, squares);
	stage('read back');

	const probeProblems = await checkProbeView(page, join(dataDir, 'probes.glb'), probeSpheres);
	await page.evaluate(() => window.vdblightPage.showProbes(true));
	const probeShot = screenshot.replace(/(\.png)?$/, '_probes.png');
	writeFileSync(probeShot, await page.screenshot());
	console.log(`screenshot: ${probeShot}`);
	stage('probe view');
	if (probeProblems.length) {
		failed = true;
		probeProblems.slice(0, 5).forEach((p) => console.error(`  probe view: ${p}`));
	}
	if (consoleErrors.length) throw new Error(`console errors: ${consoleErrors.join(' | ')}`);

	// --- vdblight query at the points three.js sampled ------------------------------------------
	const cases = [
		...glslPoints.map(([p, n], i) => ({ kind: 'glsl', p, n, e: glsl[i] })),
		...rendered.map((r) => ({ kind: 'render', p: r.position, n: r.normal, e: r.irradiance })),
	];
	const unit = (n) => { const l = Math.hypot(...n); return n.map((x) => x / l); };
	for (const c of cases) {
		c.n = unit(c.n);
		c.q = c.p.map((x, a) => x + c.n[a] * info.probe_spacing[a] * 0.5);  // three's shader: half a spacing along n
	}
	const work = mkdtempSync(join(tmpdir(), 'vdblight-web-'));
	try {
		const csv = join(work, 'points.csv');
		writeFileSync(csv, cases.map((c) => [...c.q, ...c.n].map((x) => x.toPrecision(17)).join(',')).join('\n') + '\n');
		const queryArgs = ['query', volume, '--points', csv, '--sh-order', '2'];
		if (info.depth_moments) queryArgs.push('--no-depth-weights');  // three's shader interpolates plainly
		const rows = execFileSync(cli, queryArgs, { encoding: 'utf8', stdio: ['ignore', 'pipe', 'pipe'] }).trim().split('\n').slice(1);
		if (rows.length !== cases.length) throw new Error(`query printed ${rows.length} rows for ${cases.length} points`);
		rows.forEach((row, i) => { cases[i].expected = row.split(',').slice(6, 9).map(Number); });
	} finally {
		rmSync(work, { recursive: true, force: true });
	}

	stage('query');
	// --- compare ------------------------------------------------------------------------------
	for (const kind of ['glsl', 'render']) {
		let worst = 0, maxAbs = 0, maxE = 0, bad = 0, first = null;
		for (const c of cases.filter((x) => x.kind === kind)) {
			const tol = bound(c.q, c.n);
			for (let ch = 0; ch < 3; ++ch) {
				const err = Math.abs(c.e[ch] - c.expected[ch]);
				maxAbs = Math.max(maxAbs, err);
				maxE = Math.max(maxE, c.expected[ch]);
				worst = Math.max(worst, err / tol[ch]);
				if (!(err <= tol[ch])) { bad++; first ??= { ...c, ch, err, tol: tol[ch] }; }
			}
		}
		const n = cases.filter((x) => x.kind === kind).length;
		console.log(`${kind}: ${n} points, max |E_three - E_query| = ${maxAbs.toExponential(3)} W/m^2 (largest E ${maxE.toFixed(3)}), ` +
			`worst error / tolerance = ${worst.toFixed(3)}, ${bad} channel values beyond`);
		if (bad) {
			failed = true;
			console.error(`  first: p=${first.p.map((x) => x.toFixed(5))} n=${first.n.map((x) => x.toFixed(4))} channel ${first.ch}: ` +
				`three ${first.e[first.ch]} query ${first.expected[first.ch]} (|diff| ${first.err.toExponential(3)} > ${first.tol.toExponential(3)})`);
		}
	}
} catch (e) {
	failed = true;
	console.error(`check_page: ${e.stack ?? e}`);
} finally {
	if (browser) await browser.close();
	server.close();
	rmSync(profile, { recursive: true, force: true });
}
console.log(failed ? 'FAILED' : 'the page matches vdblight query');
process.exit(failed ? 1 : 0);
