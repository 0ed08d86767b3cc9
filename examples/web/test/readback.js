// Read-back hooks of the page (loaded with ?test): what the grid gives at known points, read
// from float render targets, for test/check_page.mjs to compare with `vdblight query`.
import * as THREE from 'three';

const quadCamera = new THREE.OrthographicCamera(-1, 1, 1, -1, 0, 1);
const fullScreen = /* glsl */`void main() { gl_Position = vec4(position.xy, 0.0, 1.0); }`;

function readTarget(renderer, target) {
	const out = new Float32Array(target.width * target.height * 4);
	renderer.readRenderTargetPixels(target, 0, 0, target.width, target.height, out);
	return out;
}

/**
 * E(p, n) from the grid's own GLSL: three's lightprobes_pars_fragment chunk, unchanged, its
 * getLightProbeGridIrradiance() called once per point on a float target.
 * `points`: [x, y, z, nx, ny, nz] per point. Returns [r, g, b] per point (irradiance, W/m^2).
 */
export function evaluateGrid(renderer, grid, points) {
	const n = points.length / 6;
	const input = new Float32Array(n * 2 * 4);
	for (let i = 0; i < n; ++i)
		for (let a = 0; a < 3; ++a) {
			input[4 * i + a] = points[6 * i + a];
			input[4 * (n + i) + a] = points[6 * i + 3 + a];
		}
	const pointsTexture = new THREE.DataTexture(input, n, 2, THREE.RGBAFormat, THREE.FloatType);
	pointsTexture.needsUpdate = true;
	const material = new THREE.ShaderMaterial({
		uniforms: {
			atlas: { value: grid.texture }, pointsTexture: { value: pointsTexture },
			gridMin: { value: grid.boundingBox.min }, gridMax: { value: grid.boundingBox.max }, gridResolution: { value: grid.resolution },
		},
		vertexShader: fullScreen,
		fragmentShader: /* glsl */`
			precision highp float;
			${THREE.ShaderChunk.lightprobes_pars_fragment.replaceAll('NUM_LIGHT_PROBE_GRIDS', '1')}
			uniform highp sampler3D atlas;
			uniform highp sampler2D pointsTexture;
			uniform vec3 gridMin, gridMax, gridResolution;
			void main() {
				int i = int(gl_FragCoord.x);
				vec3 p = texelFetch(pointsTexture, ivec2(i, 0), 0).xyz;
				vec3 n = texelFetch(pointsTexture, ivec2(i, 1), 0).xyz;
				gl_FragColor = vec4(getLightProbeGridIrradiance(atlas, gridMin, gridMax, gridResolution, p, n), 1.0);
			}`,
	});
	const target = new THREE.WebGLRenderTarget(n, 1, { type: THREE.FloatType, depthBuffer: false });
	const scene = new THREE.Scene();
	scene.add(new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material));
	const previous = renderer.getRenderTarget();
	renderer.setRenderTarget(target);
	renderer.render(scene, quadCamera);
	renderer.setRenderTarget(previous);
	const rgba = readTarget(renderer, target);
	target.dispose(); material.dispose(); pointsTexture.dispose();
	return Array.from({ length: n }, (_, i) => [rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]]);
}

/**
 * The whole material path: a white MeshLambertMaterial square facing `normal`, lit only by
 * the grid, rendered head-on by an orthographic camera into a float target of
 * `pixels` x `pixels`; each pixel holds E / pi. Returns per pixel its centre's world
 * position, the normal and pi times the pixel (the irradiance three.js used).
 */
export function renderSquare(renderer, grid, { center, normal, size, pixels }) {
	const n = new THREE.Vector3(...normal).normalize();
	const c = new THREE.Vector3(...center);
	const square = new THREE.Mesh(new THREE.PlaneGeometry(size, size), new THREE.MeshLambertMaterial({ color: 0xffffff }));
	square.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), n);
	square.position.copy(c);
	const camera = new THREE.OrthographicCamera(-size / 2, size / 2, size / 2, -size / 2, 0.01, 1);
	camera.position.copy(c).addScaledVector(n, 0.5);
	camera.up.set(0, 1, 0).applyQuaternion(square.quaternion);  // the square's own y axis
	camera.lookAt(c);
	camera.updateMatrixWorld();
	const right = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 0);
	const up = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 1);

	const parent = grid.parent;
	const scene = new THREE.Scene();
	scene.add(square, grid);  // the grid is this scene's only light while it renders
	const target = new THREE.WebGLRenderTarget(pixels, pixels, { type: THREE.FloatType });
	const previous = renderer.getRenderTarget();
	renderer.setRenderTarget(target);
	renderer.render(scene, camera);
	renderer.setRenderTarget(previous);
	if (parent) parent.add(grid);
	const rgba = readTarget(renderer, target);
	target.dispose(); square.geometry.dispose(); square.material.dispose();

	const out = [];
	for (let py = 0; py < pixels; ++py)
		for (let px = 0; px < pixels; ++px) {
			const p = c.clone().addScaledVector(right, ((px + 0.5) / pixels - 0.5) * size).addScaledVector(up, ((py + 0.5) / pixels - 0.5) * size);
			const k = 4 * (py * pixels + px);
			out.push({ position: p.toArray(), normal: n.toArray(), irradiance: [0, 1, 2].map((a) => Math.PI * rgba[k + a]) });
		}
	return out;
}

/**
 * Vertices of the probe view as three draws them: the probe mesh (as GLTFLoader built it, its
 * own material and vertex colours) rendered alone, once per vertex, by an orthographic camera
 * that looks at the vertex `position` against its `normal` from just outside the surface, each
 * into its own `pixels`² viewport (odd, so that the vertex projects onto the centre pixel's
 * centre, where the rasteriser's interpolation gives exactly that vertex's attribute) of one
 * RGBA8 target, read back once. `halfWidth`: the view's half extent; `distance`: how far out
 * the camera stands (less than the gap to any other sphere). Returns per vertex the centre
 * pixel's [r, g, b, a] bytes.
 */
export function renderProbeVertices(renderer, mesh, cases, pixels = 9) {
	const parent = mesh.parent, visible = mesh.visible;
	const scene = new THREE.Scene();
	scene.add(mesh);  // alone: no walls, no box lines, no hidden ancestor
	mesh.visible = true;
	const target = new THREE.WebGLRenderTarget(pixels * cases.length, pixels);  // RGBA8, linear: no tone mapping or sRGB encoding
	const previous = renderer.getRenderTarget(), autoClear = renderer.autoClear;
	const clearColour = renderer.getClearColor(new THREE.Color()), clearAlpha = renderer.getClearAlpha();
	renderer.setRenderTarget(target);
	renderer.setClearColor(0x000000, 0);  // a pixel no sphere covers reads alpha 0
	renderer.clear();
	renderer.autoClear = false;
	cases.forEach(({ position, normal, halfWidth, distance }, i) => {
		const n = new THREE.Vector3(...normal).normalize();
		const p = new THREE.Vector3(...position);
		const camera = new THREE.OrthographicCamera(-halfWidth, halfWidth, halfWidth, -halfWidth, 0, 2 * distance);
		camera.position.copy(p).addScaledVector(n, distance);
		camera.up.set(...(Math.abs(n.y) > 0.9 ? [1, 0, 0] : [0, 1, 0]));
		camera.lookAt(p);
		camera.updateMatrixWorld();
		target.viewport.set(i * pixels, 0, pixels, pixels);
		renderer.setRenderTarget(target);  // takes the target's viewport
		renderer.clearDepth();
		renderer.render(scene, camera);
	});
	renderer.autoClear = autoClear;
	renderer.setClearColor(clearColour, clearAlpha);
	renderer.setRenderTarget(previous);
	mesh.visible = visible;
	if (parent) parent.add(mesh);
	const rgba = new Uint8Array(pixels * cases.length * pixels * 4);
	renderer.readRenderTargetPixels(target, 0, 0, pixels * cases.length, pixels, rgba);
	target.dispose();
	const row = pixels >> 1;
	return cases.map((_, i) => {
		const c = 4 * (row * pixels * cases.length + i * pixels + (pixels >> 1));
		return Array.from(rgba.slice(c, c + 4));
	});
}
