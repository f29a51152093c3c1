// threejs_sun.mjs DIR CHROMIUM [options] ORIGINAL CLOUD [CLOUD...]
//   — run through scripts/studies/threejs_sun.sh, which installs three and
//   puppeteer-core under DIR and finds CHROMIUM.
//
// How bright a model and its Billboard Clouds look in three.js under a sun.
// ORIGINAL and every CLOUD are rendered in one headless Chromium page (WebGL2
// on SwiftShader: --use-angle=swiftshader --enable-unsafe-swiftshader) with
// the same camera, an AmbientLight and a white DirectionalLight (the "sun")
// from each requested direction, and the mean colour of the pixels each
// model covers is compared.
//
// Options
//   --suns LIST        comma-separated AZ:EL in degrees, or "sweep" (default):
//                      azimuths 0,45,...,315 x elevations 15 and 50 (16 suns).
//                      "headlight": one light at the camera, for each view.
//   --views LIST       front,side (default both): camera at azimuth 0 / 90.
//   --elevation DEG    camera elevation (default 10).
//   --size PX          square canvas (default 256).
//   --fov DEG          vertical field of view of the perspective camera
//                      (default 30).
//   --ambient I        AmbientLight intensity (default 0.4).
//   --sun-intensity I  DirectionalLight intensity, white (default 1.0).
//   --json OUT.json    everything: options, per render statistics, ratios.
//   --keep DIR         PNG of every render:
//                      DIR/<original stem>_<view>_az<A>_el<E>_<orig|cloudN>.png
//   --timeout S        the whole run (default 600).
//   --original-material standard|phong
//                      standard (default): an OBJ original's Phong materials
//                      become MeshStandardMaterial (map, colour, alpha kept;
//                      metalness 0; roughness (2 / (Ns + 2))^(1/4) from the
//                      MTL's Ns, 1 without, the rule bbcgen's loader uses):
//                      the same lighting model as the glTF clouds; phong:
//                      as MTLLoader makes them (Ks/Ns specular kept).
//   --no-mipmaps       every texture (original and clouds) without mipmaps
//                      (LinearFilter): shows what three.js's default mipmaps
//                      do to alpha-tested foliage and texture atlases (the
//                      colour of transparent texels and of neighbouring atlas
//                      regions bleeds into leaves; alpha thins) — docs/lighting.md.
//   --show-normals     draws every model's shading normal (view space, after
//                      its normal map and the two-sided flip) as its colour,
//                      rgb = (n + 1) / 2, instead of lighting it: with --keep,
//                      shows whether a cloud's normals are its original's.
//   --lobe diffuse|specular
//                      every model (original and clouds alike) drawn with one
//                      term of three.js's lighting only: the diffuse (direct +
//                      ambient) or the specular (direct + ambient) reflection;
//                      shows which of the two a cloud gets wrong.
//
// Conventions
//   * Models are Y-up. Azimuth is measured around +Y: azimuth 0 is on the +Z
//     axis, 90 on +X. Camera and sun use the same convention: the sun sits in
//     direction (cos EL sin AZ, sin EL, cos EL cos AZ) from the model and its
//     light travels towards the model, so sun azimuth 0 in the front view is
//     "sun behind the camera" and 180 is backlit.
//   * Same frame for every model: the camera looks at the centre of the
//     ORIGINAL's bounding sphere (THREE.Box3 of the loaded original ->
//     getBoundingSphere) from distance radius / sin(fov / 2), so that sphere
//     fills the view; the clouds are drawn in their own coordinates with that
//     same camera (a cloud must be in its original's frame).
//   * Renderer: antialias false, no shadows, NoToneMapping, outputColorSpace
//     SRGBColorSpace, pixel ratio 1, clear colour transparent (alpha 0), so a
//     pixel is covered when its alpha is > 0. Chromium runs with puppeteer's
//     headless: true, i.e. --headless=new, and --no-sandbox.
//   * Light units: three.js (r155+) lights are physical: a lit (Phong or
//     Standard) surface of albedo A facing the sun reflects
//     A x (sun + ambient) / pi, so with the defaults (1.0 + 0.4) it reaches
//     only 0.45 A, while an unlit material (KHR_materials_unlit ->
//     MeshBasicMaterial) shows its texture as it is whatever the lights.
//     An unlit (baked) cloud's ratio therefore scales with 1 / the light
//     level; --sun-intensity 3.1416 --ambient 1.2566 (the defaults x pi)
//     give a lit surface A x (cos + 0.4), the level a bake with unit sun
//     assumes. Lit clouds are not affected.
//   * Mipmaps are three's defaults (what a user gets), so alpha-tested
//     foliage thins at low resolution: coverage and ratios depend a little
//     on --size (oak_medium, lit cloud, 2 renders: coverage ratio 1.38 at
//     128 px, 1.09 at 256, 1.06 at 512).
//   * Materials. ORIGINAL (and any .obj) is loaded with MTLLoader + OBJLoader
//     (textures relative to the .mtl, i.e. the .obj's folder): the
//     MeshPhongMaterial a three.js user gets (made a MeshStandardMaterial
//     unless --original-material phong, see above), with two changes, so
//     that foliage is drawn the way an engine draws it:
//       - every material gets side = DoubleSide (leaf cards are two-sided);
//       - a material whose map's image has an alpha channel with values
//         below 255 (PNG cut-outs), or that has an alphaMap (MTL map_d), or
//         opacity < 1, is alpha-TESTED instead of blended: transparent =
//         false, alphaTest = 0.5, depthWrite = true. (MTLLoader would make it
//         a blended transparent material, whose result depends on draw order.)
//       MTLLoader turns map_d into an alphaMap, which three.js reads from the
//       GREEN channel. When map_d names the same image as map_Kd and that
//       image has alpha (eztree's oak_color.png: an RGBA cut-out), the
//       alphaMap is dropped: the map's alpha already cuts the leaves out, as
//       the MTL means, while green x alpha under alphaTest 0.5 would throw
//       away most of the leaves (oak_medium then drew as a bare tree with
//       about a fifth of its pixels). Any other alphaMap is kept as three
//       reads it (what a user gets). The JSON lists what was done per
//       material (alphaTested, droppedAlphaMap).
//     Only faces are drawn, as bbcgen reads an OBJ: its l and p elements
//     are left out (OBJLoader would turn the whole object holding them
//     into lines or points: the Scopia acacia's trunk drew as white
//     lines); the JSON counts them (strippedElements).
//     A CLOUD .glb/.gltf is drawn exactly as GLTFLoader loads it (alphaMode
//     MASK -> alphaTest, doubleSided, normalTexture, occlusionTexture,
//     KHR_materials_unlit -> MeshBasicMaterial); nothing is changed.
//   * Every texture is loaded before anything is rendered; a file or texture
//     that fails to load fails the run (exit 4), and so does an original
//     render that covers no pixel.
//
// Measurements (per model, per sun and view): covered pixels (alpha > 0),
// mean R, G, B of the covered pixels in the 8-bit sRGB output (0-255; a
// pixel with 0 < alpha < 255 is un-premultiplied and counted as covered, the
// JSON says how many there were), and luminance = 0.2126 R + 0.7152 G +
// 0.0722 B of those means; saturation = the mean over those pixels of
// max(R, G, B) - min(R, G, B). Per cloud and render: the ratio of the cloud's
// luminance (and of each channel) to the original's, and the coverage ratio.
// Summary per cloud: min, max and mean luminance ratio over all renders and
// the number of renders with a ratio outside [0.90, 1.10] (a cloud render
// that covers nothing counts as outside).
//
// Exit status: 0 success, 1 bad command line, 2 missing file, 3 tools
// unavailable (Chromium does not start, no WebGL2), 4 a render failed (load
// error, blank original, timeout). Browser console errors and page errors
// are forwarded to stderr.
import { createRequire } from 'node:module';
import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';
import crypto from 'node:crypto';

const t0 = Date.now();
const [dir, chromium, ...argv] = process.argv.slice(2);
const prog = 'threejs_sun.sh';
const BAND = [0.9, 1.1];

function die(code, msg) {
  process.stderr.write(`${prog}: ${msg}\n`);
  process.exit(code);
}

// ---------------------------------------------------------------- options
const opt = {
  suns: 'sweep', views: 'front,side', elevation: 10, size: 256, fov: 30,
  ambient: 0.4, sunIntensity: 1.0, json: null, keep: null, timeout: 600, originalMaterial: 'standard',
};
const files = [];
{
  const num = (name, v, lo, hi) => {
    const x = Number(v);
    if (v === undefined || v === '' || !Number.isFinite(x) || x < lo || x > hi)
      die(1, `${name} wants a number in [${lo}, ${hi}], got ${v === undefined ? 'nothing' : `'${v}'`}`);
    return x;
  };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    const eq = a.startsWith('--') ? a.indexOf('=') : -1;
    const name = eq > 0 ? a.slice(0, eq) : a;
    const value = () => (eq > 0 ? a.slice(eq + 1) : argv[++i]);
    const str = () => {
      const v = value();
      if (v === undefined || v === '') die(1, `${name} wants a value`);
      return v;
    };
    switch (name) {
      case '--suns': opt.suns = str(); break;
      case '--views': opt.views = str(); break;
      case '--elevation': opt.elevation = num(name, value(), -89, 89); break;
      case '--size': opt.size = Math.round(num(name, value(), 8, 4096)); break;
      case '--fov': opt.fov = num(name, value(), 1, 170); break;
      case '--ambient': opt.ambient = num(name, value(), 0, 1e6); break;
      case '--sun-intensity': opt.sunIntensity = num(name, value(), 0, 1e6); break;
      case '--no-mipmaps': opt.noMipmaps = true; break;
      case '--show-normals': opt.showNormals = true; break;
      case '--lobe': opt.lobe = str();
        if (!['diffuse', 'specular'].includes(opt.lobe)) die(1, '--lobe: diffuse or specular');
        break;
      case '--original-material': opt.originalMaterial = str();
        if (!['standard', 'phong'].includes(opt.originalMaterial)) die(1, '--original-material: standard or phong');
        break;
      case '--json': opt.json = str(); break;
      case '--keep': opt.keep = str(); break;
      case '--timeout': opt.timeout = num(name, value(), 1, 1e6); break;
      case '--inspect': opt.inspect = true; break;
      case '--': files.push(...argv.slice(i + 1)); i = argv.length; break;
      default:
        if (a.startsWith('-') && a !== '-') die(1, `unknown option ${a} (see the header of scripts/studies/threejs_sun.mjs)`);
        files.push(a);
    }
  }
}
if (files.length < (opt.inspect ? 1 : 2))
  die(1, 'usage: threejs_sun.sh [options] ORIGINAL CLOUD [CLOUD...] | --inspect FILE...');

let suns;
if (opt.suns === 'headlight') {
  suns = [{ az: 'head', el: 'light', headlight: true }];
} else if (opt.suns === 'sweep') {
  suns = [];
  for (const el of [15, 50]) for (let az = 0; az < 360; az += 45) suns.push({ az, el });
} else {
  suns = opt.suns.split(',').map((s) => {
    const m = /^\s*(-?[0-9.]+)\s*:\s*(-?[0-9.]+)\s*$/.exec(s);
    if (!m || !Number.isFinite(+m[1]) || !Number.isFinite(+m[2]) || Math.abs(+m[2]) > 90)
      die(1, `--suns: '${s}' is not AZ:EL in degrees (or use 'sweep')`);
    return { az: +m[1], el: +m[2] };
  });
}
const VIEW_AZ = { front: 0, side: 90 };
const views = opt.views.split(',').map((v) => v.trim());
for (const v of views) if (!(v in VIEW_AZ)) die(1, `--views: unknown view '${v}' (front, side)`);
if (new Set(views).size !== views.length) die(1, '--views: a view is named twice');

const kinds = files.map((f) => {
  const ext = path.extname(f).toLowerCase();
  if (ext === '.obj') return 'obj';
  if (ext === '.glb' || ext === '.gltf') return 'gltf';
  die(1, `${f}: not .obj, .glb or .gltf`);
});
for (const f of files) {
  let st;
  try { st = fs.statSync(f); } catch { die(2, `${f}: no such file`); }
  if (!st.isFile()) die(2, `${f}: not a file`);
}
const absFiles = files.map((f) => path.resolve(f));
if (opt.keep) {
  try { fs.mkdirSync(opt.keep, { recursive: true }); } catch (e) { die(2, `--keep ${opt.keep}: ${e.message}`); }
}

// ---------------------------------------------------------------- packages
let puppeteer;
const threeDir = path.join(path.resolve(dir), 'node_modules', 'three');
try {
  puppeteer = createRequire(path.join(path.resolve(dir), 'node_modules', 'x.js'))('puppeteer-core');
} catch (e) {
  die(3, `cannot load puppeteer-core from ${dir}: ${e.message}`);
}
const versionOf = (pkg) => {
  try { return JSON.parse(fs.readFileSync(path.join(dir, 'node_modules', pkg, 'package.json'))).version; } catch { return null; }
};
if (!fs.existsSync(path.join(threeDir, 'build', 'three.module.js'))) die(3, `three is not installed under ${dir}`);

// ---------------------------------------------------------------- page code
// Runs in the browser as an ES module; three is resolved by the import map.
const PAGE_JS = String.raw`
import * as THREE from 'three';
import { OBJLoader } from 'three/addons/loaders/OBJLoader.js';
import { MTLLoader } from 'three/addons/loaders/MTLLoader.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

const errors = [];
const models = [];
let renderer, scene, camera, ambient, sun, gl, size;

function dirOf(url) { return url.slice(0, url.lastIndexOf('/') + 1); }

async function fetchText(url) {
  const r = await fetch(url);
  if (!r.ok) throw new Error(url + ': HTTP ' + r.status);
  return r.text();
}

// Does this image have an alpha channel with some value below 255?
const alphaCache = new Map();
function imageHasAlpha(img) {
  if (!img) return false;
  const key = img.currentSrc || img.src || img;
  if (alphaCache.has(key)) return alphaCache.get(key);
  let has = false;
  if (!/\.jpe?g(\?|$)/i.test(img.src || '')) {
    const w = img.naturalWidth || img.width, h = img.naturalHeight || img.height;
    const c = new OffscreenCanvas(w, h);
    const ctx = c.getContext('2d', { willReadFrequently: true });
    ctx.drawImage(img, 0, 0);
    const d = ctx.getImageData(0, 0, w, h).data;
    for (let i = 3; i < d.length; i += 4) if (d[i] < 255) { has = true; break; }
  }
  alphaCache.set(key, has);
  return has;
}

function texturesOf(root) {
  const out = new Set();
  root.traverse((o) => {
    if (!o.material) return;
    for (const m of Array.isArray(o.material) ? o.material : [o.material])
      for (const k of Object.keys(m)) if (m[k] && m[k].isTexture) out.add(m[k]);
  });
  return [...out];
}

async function loadObj(url) {
  const infosAll = {};
  const manager = new THREE.LoadingManager();
  const failed = [];
  manager.onError = (u) => failed.push(u);
  const text = await fetchText(url);
  const base = dirOf(url);
  const objLoader = new OBJLoader(manager);
  const mtls = [];
  for (const m of text.matchAll(/^[ \t]*mtllib[ \t]+(.+?)[ \t]*$/gm)) mtls.push(m[1]);
  if (mtls.length) {
    const infos = {};
    let creator = null;
    for (const name of mtls) {
      const mtlUrl = new URL(name.replace(/\\/g, '/'), base).href;
      const mtlText = await fetchText(mtlUrl);
      const mtl = new MTLLoader(manager);
      const c = mtl.parse(mtlText, dirOf(mtlUrl));
      Object.assign(infos, c.materialsInfo);
      Object.assign(infosAll, c.materialsInfo);
      if (!creator) creator = c;
    }
    creator.setMaterials(infos);
    creator.preload();
    objLoader.setMaterials(creator);
  }
  // Faces only, as bbcgen reads an OBJ: OBJLoader makes an object holding
  // any l (polyline) or p (point) element a LineSegments / Points of
  // the whole object, so a trunk group with two stray polylines would be
  // drawn as thin white lines (the Scopia acacia). The fair reference draws
  // the faces; the JSON counts what was left out.
  let strippedElements = 0;
  const faceText = text.replace(/^[ \t]*[lp][ \t][^\n]*\n?/gm, () => { strippedElements++; return ''; });
  const root = objLoader.parse(faceText);
  root.userData.strippedElements = strippedElements;
  // Wait for every texture's image (TextureLoader sets texture.image on load).
  const textures = texturesOf(root);
  const t0 = performance.now();
  while (textures.some((t) => !t.image) && !failed.length) {
    if (performance.now() - t0 > 120000) throw new Error(url + ': textures still loading after 120 s');
    await new Promise((r) => setTimeout(r, 20));
  }
  if (failed.length) throw new Error(url + ': cannot load ' + failed.join(', '));
  // Foliage: alpha-tested, two-sided (see the header of threejs_sun.mjs).
  const notes = [];
  const swaps = new Map();
  root.traverse((o) => {
    if (!o.material) return;
    for (const m of Array.isArray(o.material) ? o.material : [o.material]) {
      if (m.userData.bbcDone) continue;
      m.userData.bbcDone = true;
      m.side = THREE.DoubleSide;
      // map_d naming the map_Kd image itself (an RGBA cut-out): its alpha
      // already applies through the map; three would read the GREEN channel.
      let droppedAlphaMap = null;
      if (m.alphaMap && m.map && m.alphaMap.image && m.map.image &&
          m.alphaMap.image.src === m.map.image.src && imageHasAlpha(m.map.image)) {
        droppedAlphaMap = m.alphaMap.image.src;
        m.alphaMap = null;
      }
      const cut = (m.map && imageHasAlpha(m.map.image)) || !!m.alphaMap || !!droppedAlphaMap || m.opacity < 1;
      if (cut) {
        m.transparent = false;
        m.alphaTest = 0.5;
        m.depthWrite = true;
      }
      m.needsUpdate = true;
      if (initOpt.originalMaterial === 'standard' && m.isMeshPhongMaterial) {
        // The same material as glTF's metallic-roughness: roughness from
        // the MTL's Ns ((2 / (Ns + 2))^(1/4): Blinn-Phong's match alpha =
        // sqrt(2 / (Ns + 2)) is GGX's alpha = roughness^2; the rule
        // bbcgen's loader uses), 1 without Ns; metalness 0; Ks dropped.
        const info = infosAll[m.name] || {};
        const ns = info.ns !== undefined ? parseFloat(info.ns) : NaN;
        const st = new THREE.MeshStandardMaterial({ name: m.name, color: m.color, map: m.map,
          alphaMap: m.alphaMap, side: m.side, transparent: m.transparent, alphaTest: m.alphaTest,
          depthWrite: m.depthWrite, opacity: m.opacity, metalness: 0,
          roughness: ns > 0 ? Math.pow(2 / (ns + 2), 0.25) : 1 });
        st.userData.bbcDone = true;
        swaps.set(m, st);
      }
      notes.push({ name: m.name, type: swaps.has(m) ? 'MeshStandardMaterial (from Phong)' : m.type, alphaTested: cut, map: m.map ? m.map.image.src : null,
        alphaMap: m.alphaMap ? m.alphaMap.image.src : null, droppedAlphaMap, opacity: m.opacity,
        color: m.color ? m.color.toArray() : null,
        specular: m.specular ? m.specular.toArray() : null, shininess: m.shininess });
    }
  });
  root.traverse((o) => {
    if (!o.material) return;
    if (Array.isArray(o.material)) o.material = o.material.map((m) => swaps.get(m) || m);
    else o.material = swaps.get(o.material) || o.material;
  });
  return { root, materials: notes };
}

async function loadGltf(url) {
  const gltf = await new GLTFLoader().loadAsync(url);
  const root = gltf.scene;
  for (const t of texturesOf(root)) {
    const img = t.image;
    if (!img) throw new Error(url + ': a texture has no image');
    if (img.complete === false) await img.decode();
  }
  const notes = [];
  const seen = new Set();
  root.traverse((o) => {
    if (!o.material) return;
    for (const m of Array.isArray(o.material) ? o.material : [o.material]) {
      if (seen.has(m)) continue;
      seen.add(m);
      notes.push({ name: m.name, type: m.type, alphaTest: m.alphaTest, transparent: m.transparent,
        side: m.side, map: !!m.map, normalMap: !!m.normalMap, aoMap: !!m.aoMap });
    }
  });
  return { root, materials: notes };
}

function boxInfo(root) {
  const box = new THREE.Box3().setFromObject(root);
  const s = box.getBoundingSphere(new THREE.Sphere());
  return { min: box.min.toArray(), max: box.max.toArray(), center: s.center.toArray(), radius: s.radius };
}

let initOpt = {};
window.bbc = {
  init(o) {
    initOpt = o;
    size = o.size;
    const canvas = document.createElement('canvas');
    canvas.width = canvas.height = size;
    document.body.appendChild(canvas);
    renderer = new THREE.WebGLRenderer({ canvas, antialias: false, alpha: true,
      preserveDrawingBuffer: true, premultipliedAlpha: true });
    renderer.setPixelRatio(1);
    renderer.setSize(size, size, false);
    renderer.setClearColor(0x000000, 0);
    renderer.toneMapping = THREE.NoToneMapping;
    renderer.outputColorSpace = THREE.SRGBColorSpace;
    renderer.shadowMap.enabled = false;
    gl = renderer.getContext();
    scene = new THREE.Scene();
    ambient = new THREE.AmbientLight(0xffffff, o.ambient);
    sun = new THREE.DirectionalLight(0xffffff, o.sunIntensity);
    sun.castShadow = false;
    scene.add(ambient, sun, sun.target);
    camera = new THREE.PerspectiveCamera(o.fov, 1, 0.1, 1000);
    const dbg = gl.getExtension('WEBGL_debug_renderer_info');
    return {
      webgl2: renderer.capabilities.isWebGL2 !== false && typeof WebGL2RenderingContext !== 'undefined' && gl instanceof WebGL2RenderingContext,
      renderer: dbg ? gl.getParameter(dbg.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER),
      version: gl.getParameter(gl.VERSION),
      three: THREE.REVISION,
    };
  },

  async load(url, kind) {
    const m = kind === 'obj' ? await loadObj(url) : await loadGltf(url);
    if (initOpt.noMipmaps)
      for (const t of texturesOf(m.root)) {
        t.generateMipmaps = false;
        t.minFilter = THREE.LinearFilter;
        t.needsUpdate = true;
      }
    if (initOpt.lobe)
      m.root.traverse((o) => {
        if (!o.material) return;
        for (const mat of Array.isArray(o.material) ? o.material : [o.material]) {
          if (mat.userData.bbcLobe) continue;
          mat.userData.bbcLobe = true;
          const keep = initOpt.lobe === 'diffuse' ? 'totalSpecular' : 'totalDiffuse';
          mat.onBeforeCompile = (sh) => {
            sh.fragmentShader = sh.fragmentShader.replace(/vec3 (totalSpecular|totalDiffuse) = [^;]*;/g,
              (all, name) => (name === keep ? 'vec3 ' + name + ' = vec3( 0.0 );' : all));
          };
          mat.needsUpdate = true;
        }
      });
    if (initOpt.showNormals)
      m.root.traverse((o) => {
        if (!o.material) return;
        for (const mat of Array.isArray(o.material) ? o.material : [o.material]) {
          if (mat.userData.bbcNormals) continue;
          mat.userData.bbcNormals = true;
          mat.onBeforeCompile = (sh) => {
            sh.fragmentShader = sh.fragmentShader.replace('#include <dithering_fragment>',
              'gl_FragColor = vec4( normalize( normal ) * 0.5 + 0.5, 1.0 );');
          };
          mat.needsUpdate = true;
        }
      });
    m.root.updateMatrixWorld(true);
    let tris = 0;
    m.root.traverse((o) => {
      if (o.isMesh && o.geometry) {
        const g = o.geometry;
        tris += (g.index ? g.index.count : g.attributes.position.count) / 3;
      }
    });
    models.push(m.root);
    // What a user's scene gets: the top-level objects (a glTF scene's root
    // nodes; MSFT_lod is not read by three.js) and the meshes under them.
    let meshes = 0;
    m.root.traverse((o) => { if (o.isMesh) meshes++; });
    const roots = m.root.children.map((o) => o.name);
    return { index: models.length - 1, box: boxInfo(m.root), triangles: tris, materials: m.materials,
      roots, meshes, strippedElements: m.root.userData.strippedElements || 0 };
  },

  // Renders model i for every view and sun; returns statistics (and PNGs).
  render(i, frame, views, suns, keep) {
    const root = models[i];
    scene.add(root);
    const c = new THREE.Vector3().fromArray(frame.center);
    const d = frame.radius / Math.sin(THREE.MathUtils.degToRad(frame.fov) / 2);
    camera.near = Math.max(d - 1.5 * frame.radius, 0.01 * d);
    camera.far = d + 1.5 * frame.radius;
    camera.updateProjectionMatrix();
    const dirv = (az, el) => {
      const a = THREE.MathUtils.degToRad(az), e = THREE.MathUtils.degToRad(el);
      return new THREE.Vector3(Math.cos(e) * Math.sin(a), Math.sin(e), Math.cos(e) * Math.cos(a));
    };
    const buf = new Uint8Array(size * size * 4);
    const out = [];
    for (const v of views) {
      camera.position.copy(c).addScaledVector(dirv(v.az, frame.elevation), d);
      camera.up.set(0, 1, 0);
      camera.lookAt(c);
      camera.updateMatrixWorld(true);
      for (const s of suns) {
        if (s.headlight) sun.position.copy(camera.position);
        else sun.position.copy(c).addScaledVector(dirv(s.az, s.el), d);
        sun.target.position.copy(c);
        sun.updateMatrixWorld(true);
        sun.target.updateMatrixWorld(true);
        renderer.render(scene, camera);
        gl.readPixels(0, 0, size, size, gl.RGBA, gl.UNSIGNED_BYTE, buf);
        let n = 0, partial = 0, r = 0, g = 0, b = 0, sat = 0;
        for (let p = 0; p < buf.length; p += 4) {
          const a = buf[p + 3];
          if (a === 0) continue;
          n++;
          let pr = buf[p], pg = buf[p + 1], pb = buf[p + 2];
          if (a !== 255) {
            partial++;
            const k = 255 / a;
            pr = Math.min(255, pr * k); pg = Math.min(255, pg * k); pb = Math.min(255, pb * k);
          }
          r += pr; g += pg; b += pb;
          sat += Math.max(pr, pg, pb) - Math.min(pr, pg, pb);
        }
        const rec = { view: v.name, az: s.az, el: s.el, covered: n, partial,
          r: n ? r / n : null, g: n ? g / n : null, b: n ? b / n : null, sat: n ? sat / n : null };
        rec.lum = n ? 0.2126 * rec.r + 0.7152 * rec.g + 0.0722 * rec.b : null;
        if (initOpt.showNormals && n) {
          // The normals drawn: their mean (view space: x right, y up, z
          // towards the camera) and the shares facing away from the
          // camera (z < 0), up (y > 0.5) and down (y < -0.5).
          const mean = [0, 0, 0];
          let away = 0, up = 0, down = 0;
          for (let p = 0; p < buf.length; p += 4) {
            if (buf[p + 3] === 0) continue;
            const v = [0, 1, 2].map((k) => buf[p + k] / 127.5 - 1);
            const l = Math.hypot(v[0], v[1], v[2]) || 1;
            for (let k = 0; k < 3; k++) mean[k] += v[k] / l / n;
            if (v[2] < 0) away++;
            if (v[1] / l > 0.5) up++;
            if (v[1] / l < -0.5) down++;
          }
          rec.normals = { mean, away: away / n, up: up / n, down: down / n };
        }
        if (keep) rec.png = renderer.domElement.toDataURL('image/png');
        out.push(rec);
      }
    }
    scene.remove(root);
    return out;
  },
};
window.bbcReady = true;
`;

// ---------------------------------------------------------------- server
// Serves /<token>/three/... from the installed three package, the page, and
// /<token>/fs/<absolute path> from the file system so that relative paths in
// the models (MTL, textures, .gltf buffers) resolve. Bound to 127.0.0.1 and
// behind a random token.
const token = crypto.randomBytes(12).toString('hex');
const MIME = {
  '.js': 'text/javascript', '.mjs': 'text/javascript', '.html': 'text/html', '.json': 'application/json',
  '.png': 'image/png', '.jpg': 'image/jpeg', '.jpeg': 'image/jpeg', '.gif': 'image/gif', '.bmp': 'image/bmp',
  '.webp': 'image/webp', '.ktx2': 'image/ktx2', '.glb': 'model/gltf-binary', '.gltf': 'model/gltf+json',
  '.bin': 'application/octet-stream', '.obj': 'text/plain', '.mtl': 'text/plain',
};
const fsUrl = (abs) => `/${token}/fs` + abs.split(path.sep).map(encodeURIComponent).join('/');
const missing = [];
const server = http.createServer((req, res) => {
  const url = new URL(req.url, 'http://x');
  const p = decodeURIComponent(url.pathname);
  const send = (code, body, type) => {
    res.writeHead(code, { 'content-type': type || 'text/plain', 'cache-control': 'no-store' });
    res.end(body);
  };
  if (p === '/favicon.ico') return send(204, '');
  if (!p.startsWith(`/${token}/`)) return send(403, 'forbidden');
  const rest = p.slice(token.length + 1);
  if (rest === '/index.html') {
    const importmap = { imports: { three: `/${token}/three/build/three.module.js`, 'three/addons/': `/${token}/three/examples/jsm/` } };
    return send(200, `<!doctype html><html><head><meta charset="utf-8">
<script type="importmap">${JSON.stringify(importmap)}</script></head>
<body style="margin:0;background:#000"><script type="module" src="/${token}/page.js"></script></body></html>`, 'text/html');
  }
  if (rest === '/page.js') return send(200, PAGE_JS, 'text/javascript');
  let file;
  if (rest.startsWith('/three/')) file = path.join(threeDir, path.normalize(rest.slice(6)));
  else if (rest.startsWith('/fs/')) file = path.normalize(rest.slice(3));
  else return send(404, 'not found');
  fs.readFile(file, (err, data) => {
    if (err) {
      missing.push(file);
      return send(404, `not found: ${file}`);
    }
    send(200, data, MIME[path.extname(file).toLowerCase()] || 'application/octet-stream');
  });
});
await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
const base = `http://127.0.0.1:${server.address().port}`;

// ---------------------------------------------------------------- browser
let browser = null;
let finishing = false;
async function finish(code, msg) {
  if (finishing) return new Promise(() => {}); // the first reason wins
  finishing = true;
  if (msg) process.stderr.write(`${prog}: ${msg}\n`);
  try { if (browser) await browser.close(); } catch { /* already gone */ }
  server.close();
  process.exit(code);
}
const killer = setTimeout(() => finish(4, `timed out after ${opt.timeout} s`), opt.timeout * 1000);
killer.unref();

try {
  browser = await puppeteer.launch({
    executablePath: chromium,
    headless: true, // puppeteer passes --headless=new
    args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--no-sandbox',
      '--ignore-gpu-blocklist', '--disable-dev-shm-usage', '--no-first-run', '--disable-extensions'],
    protocolTimeout: opt.timeout * 1000,
    timeout: 60000,
  });
} catch (e) {
  await finish(3, `cannot start ${chromium}: ${e.message}`);
}
const chromiumVersion = await browser.version();
const page = await browser.newPage();
page.setDefaultTimeout(opt.timeout * 1000);
const pageErrors = [];
page.on('console', (msg) => {
  const t = msg.type();
  if (t === 'error' || t === 'warn' || t === 'warning') {
    const text = msg.text();
    // Chromium's own note that WebGL falls back to software: expected here.
    if (/GPU stall due to ReadPixels|Automatic fallback to software WebGL/.test(text)) return;
    process.stderr.write(`browser console ${t}: ${text}\n`);
    if (t === 'error') pageErrors.push(text);
  }
});
page.on('pageerror', (e) => {
  process.stderr.write(`browser page error: ${e.message}\n`);
  pageErrors.push(e.message);
});
// net::ERR_ABORTED is reported now and then for a .glb that GLTFLoader did
// read in full (FileLoader streams the body); a real loss fails the load.
page.on('requestfailed', (r) => {
  const why = r.failure()?.errorText;
  if (why !== 'net::ERR_ABORTED') process.stderr.write(`browser request failed: ${r.url()} ${why}\n`);
});

await page.goto(`${base}/${token}/index.html`);
try {
  await page.waitForFunction('window.bbcReady === true', { timeout: 60000 });
} catch {
  await finish(4, `three.js did not load in the page${pageErrors.length ? ': ' + pageErrors[0] : ''}`);
}
let gpu;
try {
  gpu = await page.evaluate((o) => window.bbc.init(o),
    { size: opt.size, fov: opt.fov, ambient: opt.ambient, sunIntensity: opt.sunIntensity,
      originalMaterial: opt.originalMaterial, noMipmaps: !!opt.noMipmaps,
      showNormals: !!opt.showNormals, lobe: opt.lobe || null });
} catch (e) {
  await finish(3, `no WebGL in Chromium: ${e.message}`);
}
if (!gpu.webgl2) await finish(3, `no WebGL2 in Chromium (renderer ${gpu.renderer})`);

// URLs of served files -> their paths, for messages.
const localPaths = (text) => text.split(`${base}/${token}/fs`).join('').replace(/(%[0-9A-Fa-f]{2})+/g, (m) => {
  try { return decodeURIComponent(m); } catch { return m; }
});

// Load every model once.
const loaded = [];
const tLoad = Date.now();
for (let i = 0; i < files.length; i++) {
  try {
    loaded.push(await page.evaluate((u, k) => window.bbc.load(u, k), base + fsUrl(absFiles[i]), kinds[i]));
  } catch (e) {
    await finish(4, `${files[i]}: load failed: ${localPaths(e.message.split('\n')[0])}`);
  }
  if (!(loaded[i].triangles > 0)) await finish(4, `${files[i]}: no triangles`);
}
if (missing.length) await finish(4, `files the models name are missing: ${[...new Set(missing)].join(', ')}`);
const loadSeconds = (Date.now() - tLoad) / 1000;
if (opt.inspect) { // what GLTFLoader makes of each file: no render
  for (let i = 0; i < files.length; i++)
    process.stdout.write(JSON.stringify({ file: files[i], roots: loaded[i].roots,
      meshes: loaded[i].meshes, triangles: loaded[i].triangles, strippedElements: loaded[i].strippedElements,
      materials: loaded[i].materials.map((m) => ({ name: m.name, alphaTest: m.alphaTest,
        map: m.map, normalMap: m.normalMap, aoMap: m.aoMap })) }) + '\n');
  await finish(0);
}

const ob = loaded[0].box;
if (!(ob.radius > 0) || !ob.center.every(Number.isFinite)) await finish(4, `${files[0]}: empty model (no bounding sphere)`);
const frame = { center: ob.center, radius: ob.radius, fov: opt.fov, elevation: opt.elevation };
const viewList = views.map((v) => ({ name: v, az: VIEW_AZ[v] }));
for (let i = 1; i < files.length; i++) {
  const b = loaded[i].box;
  const off = Math.hypot(...b.center.map((x, k) => x - ob.center[k]));
  if (!(b.radius > 0)) await finish(4, `${files[i]}: empty model`);
  if (off > 0.25 * ob.radius || Math.abs(b.radius / ob.radius - 1) > 0.25)
    process.stderr.write(`${prog}: warning: ${files[i]} is not in the original's frame ` +
      `(bounding sphere centre off by ${off.toPrecision(3)}, radius ${b.radius.toPrecision(3)} vs ${ob.radius.toPrecision(3)})\n`);
}

// Render.
const tRender = Date.now();
const stem = path.basename(files[0]).replace(/\.[^.]*$/, '');
const results = [];
for (let i = 0; i < files.length; i++) {
  let recs;
  try {
    recs = await page.evaluate((k, f, v, s, keep) => window.bbc.render(k, f, v, s, keep),
      loaded[i].index, frame, viewList, suns, !!opt.keep);
  } catch (e) {
    await finish(4, `${files[i]}: render failed: ${e.message.split('\n')[0]}`);
  }
  const tag = i === 0 ? 'orig' : `cloud${i - 1}`;
  for (const r of recs) {
    if (r.png) {
      const name = `${stem}_${r.view}_az${r.az}_el${r.el}_${tag}.png`;
      fs.writeFileSync(path.join(opt.keep, name), Buffer.from(r.png.split(',')[1], 'base64'));
      r.png = name;
    }
  }
  results.push(recs);
}
const renderSeconds = (Date.now() - tRender) / 1000;
if (pageErrors.length) await finish(4, `the page reported ${pageErrors.length} error(s); first: ${pageErrors[0]}`);
const blank = results[0].filter((r) => !r.covered);
if (blank.length)
  await finish(4, `${files[0]}: the original covers no pixel in ${blank.length} render(s), e.g. ${blank[0].view} sun ${blank[0].az}:${blank[0].el}`);

// ---------------------------------------------------------------- report
const ratio = (a, b) => (a == null || b == null || b === 0 ? null : a / b);
const combos = results[0].map((o, j) => ({
  view: o.view, sun: { az: o.az, el: o.el },
  original: o,
  clouds: results.slice(1).map((rs) => {
    const c = rs[j];
    return {
      ...c,
      lumRatio: ratio(c.lum, o.lum), satRatio: ratio(c.sat, o.sat), rRatio: ratio(c.r, o.r), gRatio: ratio(c.g, o.g), bRatio: ratio(c.b, o.b),
      coverageRatio: ratio(c.covered, o.covered),
    };
  }),
}));
const stats = (xs) => {
  const v = xs.filter((x) => x != null);
  return v.length ? { min: Math.min(...v), max: Math.max(...v), mean: v.reduce((a, b) => a + b, 0) / v.length } : { min: null, max: null, mean: null };
};
const summary = files.slice(1).map((f, k) => {
  const lr = combos.map((c) => c.clouds[k].lumRatio);
  const s = stats(lr);
  return {
    file: f,
    lumRatio: s,
    outside: lr.filter((x) => x == null || x < BAND[0] || x > BAND[1]).length,
    blank: combos.filter((c) => !c.clouds[k].covered).length,
    renders: lr.length,
    rRatio: stats(combos.map((c) => c.clouds[k].rRatio)),
    gRatio: stats(combos.map((c) => c.clouds[k].gRatio)),
    bRatio: stats(combos.map((c) => c.clouds[k].bRatio)),
    coverageRatio: stats(combos.map((c) => c.clouds[k].coverageRatio)),
    satRatio: stats(combos.map((c) => c.clouds[k].satRatio)),
    satOutside: combos.filter((c) => c.clouds[k].satRatio == null || Math.abs(c.clouds[k].satRatio - 1) > 0.15).length,
  };
});

const f3 = (x) => (x == null ? '  -  ' : x.toFixed(3));
console.log(`original ${files[0]}`);
files.slice(1).forEach((f, k) => console.log(`cloud${k}   ${f}`));
console.log(`${gpu.renderer}; ${opt.size} px, fov ${opt.fov}, camera elevation ${opt.elevation}, ambient ${opt.ambient}, sun ${opt.sunIntensity}`);
console.log(['view ', '  sun   ', 'orig lum', ...files.slice(1).map((_, k) => `cloud${k}`)].join('  '));
for (const c of combos) {
  const sunTxt = `${String(c.sun.az).padStart(3)}:${String(c.sun.el).padEnd(3)}`;
  console.log([c.view.padEnd(5), sunTxt.padEnd(8), c.original.lum.toFixed(1).padStart(8),
    ...c.clouds.map((x) => f3(x.lumRatio).padStart(6))].join('  '));
}
console.log(`luminance ratio cloud/original over ${combos.length} renders (band ${BAND[0].toFixed(2)}-${BAND[1].toFixed(2)}):`);
summary.forEach((s, k) => console.log(
  `cloud${k}: min ${f3(s.lumRatio.min)} max ${f3(s.lumRatio.max)} mean ${f3(s.lumRatio.mean)} ` +
  `outside ${s.outside}/${s.renders}; saturation ratio ${f3(s.satRatio.min)}-${f3(s.satRatio.max)} ` +
  `(${s.satOutside} beyond 15 %); coverage ratio ${f3(s.coverageRatio.min)}-${f3(s.coverageRatio.max)}` +
  (s.blank ? `; ${s.blank} blank render(s)` : '')));
if (opt.showNormals) {
  // --show-normals: the colours are normals; what they say, per render.
  console.log('normals drawn (view space): mean x y z, shares facing away / up / down');
  for (const c of combos)
    [c.original, ...c.clouds].forEach((x, k) => {
      if (!x.normals) return;
      const nm = x.normals;
      console.log([c.view.padEnd(5), `${c.sun.az}:${c.sun.el}`.padEnd(8), (k ? `cloud${k - 1}` : 'orig').padEnd(7),
        nm.mean.map((v) => v.toFixed(3).padStart(6)).join(' '),
        [nm.away, nm.up, nm.down].map((v) => v.toFixed(3)).join(' / ')].join('  '));
    });
}
const totalSeconds = (Date.now() - t0) / 1000;
console.log(`time ${totalSeconds.toFixed(1)} s (load ${loadSeconds.toFixed(1)} s, render ${renderSeconds.toFixed(1)} s)`);

if (opt.json) {
  const out = {
    tool: 'threejs_sun',
    options: { ...opt, suns, views: viewList, band: BAND },
    versions: { three: versionOf('three'), puppeteerCore: versionOf('puppeteer-core'), chromium: chromiumVersion, webgl: gpu },
    frame: { ...frame, distance: frame.radius / Math.sin(opt.fov * Math.PI / 360) },
    models: files.map((f, i) => ({ file: f, role: i === 0 ? 'original' : `cloud${i - 1}`, kind: kinds[i],
      box: loaded[i].box, triangles: loaded[i].triangles, strippedElements: loaded[i].strippedElements,
      materials: loaded[i].materials.map((m) => Object.fromEntries(Object.entries(m).map(([k, v]) =>
        [k, typeof v === 'string' && v.startsWith(base) ? localPaths(v) : v]))) })),
    combos, summary,
    seconds: { total: totalSeconds, load: loadSeconds, render: renderSeconds },
  };
  fs.writeFileSync(opt.json, JSON.stringify(out, null, 1) + '\n');
}
await finish(0);
