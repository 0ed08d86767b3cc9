// A static file server for the page (no dependencies, loopback only): examples/web/ at /,
// and the bake's files (probe_grid.json, probe_grid_sh.bin, scene.gltf, probes.glb) at /data/.
//
//   node examples/web/serve.mjs --data DIR [--port 8080]     # prints the page's address
//
// The test (test/check_page.mjs) imports startServer() and serves on a free port.
import { createServer } from 'node:http';
import { createReadStream, statSync } from 'node:fs';
import { resolve, sep, extname, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';

export const webRoot = dirname(fileURLToPath(import.meta.url));

const types = {
	'.html': 'text/html; charset=utf-8', '.js': 'text/javascript; charset=utf-8', '.mjs': 'text/javascript; charset=utf-8',
	'.json': 'application/json', '.gltf': 'model/gltf+json', '.bin': 'application/octet-stream', '.css': 'text/css',
	'.png': 'image/png', '.glb': 'model/gltf-binary',
};

// The file for a URL path, or null when it lies outside the served folders.
function fileFor(urlPath, dataDir) {
	let path;
	try { path = decodeURIComponent(urlPath.split('?')[0]); } catch { return null; }
	const [root, rest] = path.startsWith('/data/') ? [dataDir, path.slice(6)] : [webRoot, path.slice(1) || 'index.html'];
	const file = resolve(root, rest);
	return file.startsWith(resolve(root) + sep) ? file : null;
}

/// Starts serving; resolves to { server, url } once listening (port 0: any free port).
export function startServer({ dataDir, port = 0, host = '127.0.0.1' }) {
	const server = createServer((req, res) => {
		const file = fileFor(req.url, resolve(dataDir));
		let size = -1;
		try { if (file) size = statSync(file).isFile() ? statSync(file).size : -1; } catch { /* missing */ }
		if (size < 0) {
			res.writeHead(404, { 'Content-Type': 'text/plain' });
			res.end(`not found: ${req.url}\n`);
			return;
		}
		res.writeHead(200, { 'Content-Type': types[extname(file)] ?? 'application/octet-stream', 'Content-Length': size,
			'Cache-Control': 'no-store' });
		createReadStream(file).pipe(res);
	});
	return new Promise((ok, fail) => {
		server.once('error', fail);
		server.listen(port, host, () => ok({ server, url: `http://${host}:${server.address().port}/` }));
	});
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
	const args = process.argv.slice(2);
	const option = (name, fallback) => { const i = args.indexOf(name); return i >= 0 ? args[i + 1] : fallback; };
	const dataDir = option('--data');
	if (!dataDir) {
		console.error('usage: node serve.mjs --data DIR [--port N]  (DIR: vdblight export --format three output + scene.gltf)');
		process.exit(2);
	}
	const { url } = await startServer({ dataDir, port: Number(option('--port', 8080)) });
	console.log(`vdblight web page: ${url}  (Ctrl-C to stop)`);
}
