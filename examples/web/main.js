// The page: the baked scene (data/scene.gltf) and moving spheres, all lit by vdblight's volume
// through three.js's LightProbeGridWebGL (filled from data/probe_grid.json by the loader), and
// the glTF probe view of `export --format gltf` (data/probes.glb), shown by its button or P.
// URL parameters: t=SECONDS freezes the animation at that time (screenshots); probes starts
// with the probe view shown; test loads the read-back hooks that the test (test/check_page.mjs) calls.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { loadProbeGrid } from './vdblight-loader.js';
import { loadProbeView } from './probe-view.js';

const params = new URLSearchParams(location.search);
const fixedTime = params.has('t') ? Number(params.get('t')) : null;
const label = document.getElementById('label');
const page = { frames: 0, error: null };
window.vdblightPage = page;

// The spheres move where the Cornell box is free (above the tall block, beside the short one).
function sphereMotion(i, t) {
	if (i === 3) return [0.43, 0.07 + 0.2 * Math.abs(Math.sin(1.7 * t)), 0.12];
	const a = 0.6 * t + i * 2.0944;
	return [0.278 + 0.16 * Math.cos(a), 0.37 + 0.035 * i, 0.30 + 0.16 * Math.sin(a)];
}

async function main() {
	const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
	renderer.setPixelRatio(window.devicePixelRatio);
	renderer.setSize(window.innerWidth, window.innerHeight);
	renderer.toneMapping = THREE.ACESFilmicToneMapping;
	document.body.appendChild(renderer.domElement);

	const scene = new THREE.Scene();
	scene.background = new THREE.Color(0x111111);
	const camera = new THREE.PerspectiveCamera(40, window.innerWidth / window.innerHeight, 0.01, 10);
	camera.position.set(0.278, 0.274, -0.72);
	const controls = new OrbitControls(camera, renderer.domElement);
	controls.target.set(0.278, 0.274, 0.28);
	controls.update();

	// The probe view is optional: a data folder without probes.glb still shows the lit scene.
	const [gltf, grid, probeView] = await Promise.all([new GLTFLoader().loadAsync('data/scene.gltf'), loadProbeGrid('data/'),
		loadProbeView('data/probes.glb').catch((e) => ({ error: String(e.message ?? e) }))]);
	scene.add(gltf.scene);
	scene.add(grid);  // no other light: walls and spheres take their light from the bake alone
	if (probeView.root) scene.add(probeView.root);

	const colours = [0xffffff, 0xffc870, 0x80b0ff, 0xe0e0e0];
	const spheres = colours.map((c) => {
		const mesh = new THREE.Mesh(new THREE.SphereGeometry(0.045, 48, 24),
			new THREE.MeshStandardMaterial({ color: c, roughness: 0.9, metalness: 0 }));
		scene.add(mesh);
		return mesh;
	});

	const info = grid.userData.vdblight;
	const [nx, ny, nz] = info.resolution;
	label.innerHTML = `<b>vdblight</b> bake in three.js r${THREE.REVISION}: LightProbeGridWebGL of ${nx} &times; ${ny} &times; ${nz} ` +
		`L2 probes (${info.texture.type}), no lights but the bake<br>` + (probeView.root
		? `<button id="probes">probe view</button> (P): ${probeView.spheres} spheres of probes.glb, coloured by E(n) / &pi;`
		: `no probe view (${probeView.error})`);
	// Shows the probe spheres instead of the moving ones (the room stays); renders at once, as a
	// frozen page draws no more frames.
	const showProbes = (on) => {
		if (!probeView.root) return;
		probeView.root.visible = on;
		spheres.forEach((s) => { s.visible = !on; });
		renderer.render(scene, camera);
	};
	document.getElementById('probes')?.addEventListener('click', () => showProbes(!probeView.root.visible));
	window.addEventListener('keydown', (e) => { if (e.key === 'p' || e.key === 'P') showProbes(!probeView.root?.visible); });
	Object.assign(page, { renderer, scene, camera, grid, info, probeView, showProbes });
	if (params.has('test')) page.readback = await import('./test/readback.js');

	window.addEventListener('resize', () => {
		camera.aspect = window.innerWidth / window.innerHeight;
		camera.updateProjectionMatrix();
		renderer.setSize(window.innerWidth, window.innerHeight);
	});
	if (params.has('probes')) showProbes(true);
	renderer.setAnimationLoop((ms) => {
		const t = fixedTime ?? ms / 1000;
		spheres.forEach((s, i) => s.position.set(...sphereMotion(i, t)));
		renderer.render(scene, camera);
		// A frozen time needs no more frames (software WebGL in tests and screenshots).
		if (++page.frames >= 3 && fixedTime !== null) renderer.setAnimationLoop(null);
	});
}

main().catch((e) => {
	page.error = String(e && e.stack || e);
	label.textContent = `error: ${e.message ?? e}`;
	console.error(e);
});
