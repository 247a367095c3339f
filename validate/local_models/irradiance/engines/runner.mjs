// One Node process per engine per run: `node runner.mjs three|babylon`.
//
// Protocol (stdin → stdout), one frame per message:
//   u32 little-endian header length · header (UTF-8 JSON) · payload (header.payload_bytes raw bytes)
// Requests:
//   {op: "project", key, size, type: "float32"|"float16", clamp: bool}
//       payload: 6 faces (+X, −X, +Y, −Y, +Z, −Z), each size × size RGBA texels, rows in the order
//       the engine reads them (OpenGL cube-map layout: row i at t = (i + ½)/size, column j at
//       s = (j + ½)/size); float32, or IEEE half bits (uint16) for "float16".
//       reply: {coefficients: {...}} — the engine's own numbers, kept under `key`.
//   {op: "project_panorama", key, width, height, size}   (Babylon only)
//       payload: the lat-long panorama, height × width RGB float32, rows top (zenith) first; the engine
//       makes its own faces (PanoramaToCubeMapTools) and projects them; reply payload: those faces,
//       6 × size × size RGB float32 in Babylon's order right, left, up, down, front, back. The projection
//       with the clamp is kept under `key`, the one without (MAX_HDRI_VALUE = ∞) under `key:unclamped`.
//   {op: "evaluate", key, path, count}
//       payload: count × 3 float64 unit normals; reply payload: count × 3 float64 irradiance E
//       evaluated exactly as the engine's shader (or CPU helper) does for `path`.
//   {op: "forget", key} / {op: "ping"}
// Every reply carries {ok: true} or {ok: false, error: "<one line>"}.
import process from 'node:process';

const engineName = process.argv[2];
const engine = engineName === 'three' ? await import('./three_engine.mjs')
  : engineName === 'babylon' ? await import('./babylon_engine.mjs') : null;
if (!engine) {
  process.stderr.write(`runner.mjs: unknown engine ${engineName}\n`);
  process.exit(2);
}

const states = new Map();
let pending = Buffer.alloc(0);  // the bytes of the frame being read
let busy = Promise.resolve();

function send(header, payload) {
  const body = payload ? Buffer.from(payload.buffer, payload.byteOffset, payload.byteLength) : Buffer.alloc(0);
  const head = Buffer.from(JSON.stringify({ ...header, payload_bytes: body.length }), 'utf8');
  const len = Buffer.alloc(4);
  len.writeUInt32LE(head.length, 0);
  process.stdout.write(Buffer.concat([len, head, body]));
}

function aligned(buf, Ctor) {
  // Typed views need aligned offsets: copy the payload into its own ArrayBuffer.
  const copy = new Uint8Array(buf.length);
  copy.set(buf);
  return new Ctor(copy.buffer);
}

async function handle(header, payload) {
  try {
    if (header.op === 'ping') {
      send({ ok: true, engine: engineName, versions: engine.versions() });
    } else if (header.op === 'project') {
      const Ctor = header.type === 'float16' ? Uint16Array : Float32Array;
      const all = aligned(payload, Ctor);
      const n = header.size * header.size * 4;
      if (all.length !== 6 * n) throw new Error(`expected ${6 * n} values, got ${all.length}`);
      const faces = [0, 1, 2, 3, 4, 5].map((f) => all.subarray(f * n, (f + 1) * n));
      const state = await engine.project(faces, header);
      states.set(header.key, state);
      send({ ok: true, coefficients: state.coefficients });
    } else if (header.op === 'project_panorama') {
      if (!engine.projectPanorama) throw new Error(`${engineName}: no CPU panorama path`);
      const panorama = aligned(payload, Float32Array);
      if (panorama.length !== 3 * header.width * header.height) {
        throw new Error(`expected ${3 * header.width * header.height} values, got ${panorama.length}`);
      }
      const { state, unclamped, faces } = await engine.projectPanorama(panorama, header);
      states.set(header.key, state);
      states.set(`${header.key}:unclamped`, unclamped);
      send({ ok: true, coefficients: state.coefficients }, faces);
    } else if (header.op === 'evaluate') {
      const state = states.get(header.key);
      if (!state) throw new Error(`no projection under key ${header.key}`);
      const normals = aligned(payload, Float64Array);
      if (normals.length !== 3 * header.count) throw new Error(`expected ${3 * header.count} normal components`);
      send({ ok: true }, engine.evaluate(state, header.path, normals, header.count));
    } else if (header.op === 'forget') {
      states.delete(header.key);
      send({ ok: true });
    } else {
      throw new Error(`unknown op ${header.op}`);
    }
  } catch (err) {
    send({ ok: false, error: String(err && err.message ? err.message : err).split('\n')[0] });
  }
}

// Chunks are joined only once a whole frame has arrived (joining on every 64 KiB chunk would copy a
// megabyte panorama hundreds of times over).
const chunks = [];
let buffered = 0;
let need = 4;
process.stdin.on('data', (chunk) => {
  chunks.push(chunk);
  buffered += chunk.length;
  if (buffered < need) return;
  pending = chunks.length === 1 ? chunks[0] : Buffer.concat(chunks, buffered);
  chunks.length = 0;
  for (;;) {
    need = 4;
    if (pending.length < 4) break;
    const hlen = pending.readUInt32LE(0);
    need = 4 + hlen;
    if (pending.length < need) break;
    const header = JSON.parse(pending.subarray(4, 4 + hlen).toString('utf8'));
    const plen = header.payload_bytes || 0;
    need = 4 + hlen + plen;
    if (pending.length < need) break;
    const payload = pending.subarray(4 + hlen, 4 + hlen + plen);
    pending = pending.subarray(4 + hlen + plen);
    need = 4;
    busy = busy.then(() => handle(header, payload));
  }
  if (pending.length) chunks.push(pending);
  buffered = pending.length;
});
process.stdin.on('end', () => { busy.then(() => process.exit(0)); });
