// raycast's preview: the scene as the course's OpenGL viewer draws it, in WebGL2.
//
// The viewer lit each vertex with OpenGL 1.x's fixed-function model (local viewer, two-sided,
// the scene's ambient light, GL_NORMALIZE) and interpolated the colours; the vertex shader
// below computes the same sum, in world space (the view matrix is a rigid motion, under which
// the eye-space sum is the same). The camera moves as the staff's viewer moves it.
"use strict";

const token = new URLSearchParams(location.search).get("token") || "";
const withToken = (path) => `${path}${path.includes("?") ? "&" : "?"}token=${encodeURIComponent(token)}`;

const canvas = document.getElementById("preview");
const gl = canvas.getContext("webgl2", {
  antialias: false,
  preserveDrawingBuffer: true,
  depth: true,
  alpha: false,
});

// The vertex shader for a scene of `lights` lights (the loop unrolled by the compiler), with
// or without highlights. Each vertex is lit on both sides, as OpenGL's two-sided lighting
// does; the fragment takes the side the eye sees (OpenGL decides by the triangle's winding on
// screen, which is what gl_FrontFacing tells).
function vertexSource(lights, highlights) {
  const highlight = lights === 0 || !highlights ? "" : `
  vec3 toEye = normalize(eye - position);
  vec3 n = normalize(normal);
  for (int i = 0; i < ${lights}; i++) {
    vec4 at = lightPosition[i];
    vec3 toLight = at.w == 0.0 ? at.xyz : normalize(at.xyz - position);
    float nl = dot(n, toLight);
    vec3 halfway = normalize(toLight + toEye);
    if (nl > 0.0) front += specularMaterial * lightColour[i] * term(dot(n, halfway));
    if (nl < 0.0) back += specularMaterial * lightColour[i] * term(-dot(n, halfway));
  }`;
  return `#version 300 es
in vec3 position;
in vec3 normal;
in vec3 lightFront;
in vec3 lightBack;
uniform mat4 viewProjection;
uniform vec3 eye;
uniform vec3 sceneAmbient;
uniform vec3 ambientMaterial;
uniform vec3 diffuseMaterial;
uniform vec3 specularMaterial;
uniform float shininess;
${lights > 0 ? `uniform vec4 lightPosition[${lights}];\nuniform vec3 lightColour[${lights}];` : ""}
out vec3 frontColour;
out vec3 backColour;
// SPECULAR_FIX's later passes meet the first one's depths exactly (GL_EQUAL), whichever of the
// programs draws them.
invariant gl_Position;

float term(float nh) {
  return shininess == 0.0 ? 1.0 : pow(max(nh, 0.0), shininess);
}

void main() {
  // The ambient and diffuse terms: the light reaching each side was summed when the scene was
  // read (it does not depend on the camera); the highlight depends on the eye.
  vec3 ambient = ambientMaterial * sceneAmbient;
  vec3 front = ambient + diffuseMaterial * lightFront;
  vec3 back = ambient + diffuseMaterial * lightBack;${highlight}
  frontColour = clamp(front, 0.0, 1.0);
  backColour = clamp(back, 0.0, 1.0);
  gl_Position = viewProjection * vec4(position, 1.0);
}`;
}

const fragmentSource = `#version 300 es
precision highp float;
in vec3 frontColour;
in vec3 backColour;
out vec4 fragment;
void main() {
  fragment = vec4(gl_FrontFacing ? frontColour : backColour, 1.0);
}`;

function compile(type, source) {
  const shader = gl.createShader(type);
  gl.shaderSource(shader, source);
  gl.compileShader(shader);
  if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(shader));
  return shader;
}

const UNIFORMS = ["viewProjection", "eye", "sceneAmbient", "ambientMaterial", "diffuseMaterial",
  "specularMaterial", "shininess", "lightPosition", "lightColour"];
const buffer = gl.createBuffer();
const programs = new Map();

// The program for `lights` lights, with or without highlights, with its uniforms and vertex
// layout; made once each.
function programFor(lights, highlights) {
  const key = `${lights}:${highlights}`;
  if (programs.has(key)) return programs.get(key);
  const program = gl.createProgram();
  gl.attachShader(program, compile(gl.VERTEX_SHADER, vertexSource(lights, highlights)));
  gl.attachShader(program, compile(gl.FRAGMENT_SHADER, fragmentSource));
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(program));
  const uniform = {};
  for (const name of UNIFORMS) uniform[name] = gl.getUniformLocation(program, name);
  const vertexArray = gl.createVertexArray();
  gl.bindVertexArray(vertexArray);
  gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
  const layout = [["position", 0], ["normal", 12], ["lightFront", 24], ["lightBack", 36]];
  for (const [name, offset] of layout) {
    // An attribute the shader does not use (the normal, without highlights) is not fetched.
    const at = gl.getAttribLocation(program, name);
    if (at < 0) continue;
    gl.enableVertexAttribArray(at);
    gl.vertexAttribPointer(at, 3, gl.FLOAT, false, 48, offset);
  }
  const made = { program, uniform, vertexArray };
  programs.set(key, made);
  return made;
}

// The ray tree's lines: flat colours, no lighting (the staff's RayTree::paint).
const lineProgram = (() => {
  const program = gl.createProgram();
  gl.attachShader(program, compile(gl.VERTEX_SHADER, `#version 300 es
in vec3 position;
uniform mat4 viewProjection;
void main() { gl_Position = viewProjection * vec4(position, 1.0); }`));
  gl.attachShader(program, compile(gl.FRAGMENT_SHADER, `#version 300 es
precision highp float;
uniform vec4 colour;
out vec4 fragment;
void main() { fragment = colour; }`));
  gl.linkProgram(program);
  const vertexArray = gl.createVertexArray();
  const lines = gl.createBuffer();
  gl.bindVertexArray(vertexArray);
  gl.bindBuffer(gl.ARRAY_BUFFER, lines);
  const at = gl.getAttribLocation(program, "position");
  gl.enableVertexAttribArray(at);
  gl.vertexAttribPointer(at, 3, gl.FLOAT, false, 12, 0);
  return {
    program, vertexArray, lines,
    viewProjection: gl.getUniformLocation(program, "viewProjection"),
    colour: gl.getUniformLocation(program, "colour"),
  };
})();

// ---- Vectors and matrices (column-major, as OpenGL's) ----
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const normalize = (a) => { const l = Math.hypot(a[0], a[1], a[2]); return l > 0 ? scale(a, 1 / l) : a; };

function multiply(a, b) {
  const out = new Array(16).fill(0);
  for (let c = 0; c < 4; c++) for (let r = 0; r < 4; r++) for (let k = 0; k < 4; k++) out[c * 4 + r] += a[k * 4 + r] * b[c * 4 + k];
  return out;
}

// gluLookAt
function lookAt(eye, target, up) {
  const f = normalize(sub(target, eye));
  const s = normalize(cross(f, up));
  const u = cross(s, f);
  return [s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0,
    -dot(s, eye), -dot(u, eye), dot(f, eye), 1];
}

// glOrtho
function ortho(l, r, b, t, n, f) {
  return [2 / (r - l), 0, 0, 0, 0, 2 / (t - b), 0, 0, 0, 0, -2 / (f - n), 0,
    -(r + l) / (r - l), -(t + b) / (t - b), -(f + n) / (f - n), 1];
}

// gluPerspective, fovy in degrees
function perspective(fovy, aspect, n, f) {
  const c = 1 / Math.tan((fovy * Math.PI) / 360);
  return [c / aspect, 0, 0, 0, 0, c, 0, 0, 0, 0, (f + n) / (n - f), -1, 0, 0, (2 * f * n) / (n - f), 0];
}

// The staff's Matrix::MakeAxisRotation (Rodrigues), applied to a vector.
function rotate(v, axis, angle) {
  const [x, y, z] = axis;
  const c = Math.cos(angle), s = Math.sin(angle), t = 1 - c;
  return [
    (t * x * x + c) * v[0] + (t * x * y - s * z) * v[1] + (t * x * z + s * y) * v[2],
    (t * x * y + s * z) * v[0] + (t * y * y + c) * v[1] + (t * y * z - s * x) * v[2],
    (t * x * z - s * y) * v[0] + (t * y * z + s * x) * v[1] + (t * z * z + c) * v[2],
  ];
}

// ---- The camera, as the staff's camera_additions move it ----
const NEAR = 0.5, FAR = 40.0;
let fileCamera = null;
let camera = null;

function cameraFrom(spec) {
  return {
    kind: spec.kind,
    center: spec.center.slice(),
    direction: normalize(spec.direction),
    // The file's up, kept: "screen up" is worked out from it at each move.
    up: normalize(spec.up),
    size: spec.size,
    angle: spec.angle,
  };
}

function dolly(distance) {
  camera.center = add(camera.center, scale(camera.direction, distance));
}

function truck(dx, dy) {
  const horizontal = normalize(cross(camera.direction, camera.up));
  const screenUp = cross(horizontal, camera.direction);
  camera.center = add(camera.center, add(scale(horizontal, dx), scale(screenUp, dy)));
}

function rotateCamera(rx, ry) {
  const horizontal = normalize(cross(camera.direction, camera.up));
  const tilt = Math.acos(Math.max(-1, Math.min(1, dot(camera.up, camera.direction))));
  if (tilt - ry > 3.13) ry = tilt - 3.13;
  else if (tilt - ry < 0.01) ry = tilt - 0.01;
  // R(up, rx) R(horizontal, ry): the tilt first; the camera orbits the world's origin.
  const turn = (v) => rotate(rotate(v, horizontal, ry), camera.up, rx);
  camera.center = turn(camera.center);
  camera.direction = turn(camera.direction);
  if (camera.kind === "perspective") camera.direction = normalize(camera.direction);
}

function matrices(width, height) {
  let projection;
  if (camera.kind === "orthographic") {
    const s = camera.size;
    projection = width > height
      ? ortho(-s / 2, s / 2, (-s * height) / width / 2, (s * height) / width / 2, NEAR, FAR)
      : ortho((-s * width) / height / 2, (s * width) / height / 2, -s / 2, s / 2, NEAR, FAR);
  } else {
    // The staff's viewer took the angle back to degrees with π written 3.14159.
    const fovy = ((camera.angle * Math.PI) / 180) * (180 / 3.14159);
    projection = perspective(fovy, width / height, NEAR, FAR);
  }
  const view = lookAt(camera.center, add(camera.center, camera.direction), camera.up);
  return multiply(projection, view);
}

const number = (x) => {
  const rounded = Math.abs(x) < 5e-7 ? 0 : x;
  return String(Number(rounded.toPrecision(6)));
};
const triple = (v) => v.map(number).join(" ");

function cameraText() {
  const lines = [
    `${camera.kind === "orthographic" ? "OrthographicCamera" : "PerspectiveCamera"} {`,
    `    center ${triple(camera.center)}`,
    `    direction ${triple(camera.direction)}`,
    `    up ${triple(camera.up)}`,
    camera.kind === "orthographic" ? `    size ${number(camera.size)}` : `    angle ${number(camera.angle)}`,
    "}",
  ];
  return lines.join("\n");
}

// ---- Drawing ----
let scene = null;
let version = 0;
let frames = 0;
let pending = false;
const frameTimes = [];

// The material as the staff's glSetMaterial sets it, in one of SPECULAR_FIX's passes: the
// highlight alone, then times N.L (diffuse one, no ambient), then plus ambient and diffuse.
function materialColours(material, pass) {
  const zero = [0, 0, 0], one = [1, 1, 1];
  if (!scene.specular_fix) return [material.diffuse, material.diffuse, material.specular];
  if (pass === 0) return [zero, zero, material.specular];
  if (pass === 1) return [zero, one, zero];
  return [material.diffuse, material.diffuse, zero];
}

// One pass over the scene (the staff's Group::paint): each batch with its material.
function paint(pass, width, height) {
  const viewProjection = new Float32Array(matrices(width, height));
  for (const batch of scene.batches) {
    const material = scene.materials[batch.material];
    const [ambient, diffuse, specular] = materialColours(material, pass);
    const highlights = specular.some((c) => c !== 0);
    const { program, uniform, vertexArray } = programFor(scene.lights.length, highlights);
    gl.useProgram(program);
    gl.bindVertexArray(vertexArray);
    gl.uniformMatrix4fv(uniform.viewProjection, false, viewProjection);
    gl.uniform3fv(uniform.eye, camera.center);
    gl.uniform3fv(uniform.sceneAmbient, scene.ambient);
    if (scene.lights.length > 0 && highlights) {
      gl.uniform4fv(uniform.lightPosition, scene.lights.flatMap((l) => l.position));
      gl.uniform3fv(uniform.lightColour, scene.lights.flatMap((l) => l.colour));
    }
    gl.uniform3fv(uniform.ambientMaterial, ambient);
    gl.uniform3fv(uniform.diffuseMaterial, diffuse);
    gl.uniform3fv(uniform.specularMaterial, specular);
    gl.uniform1f(uniform.shininess, material.exponent);
    gl.drawArrays(gl.TRIANGLES, batch.first, batch.count);
  }
}

function draw() {
  pending = false;
  if (!scene) return;
  const width = canvas.width, height = canvas.height;
  gl.viewport(0, 0, width, height);
  const [r, g, b] = scene.background;
  gl.clearColor(r, g, b, 1);
  gl.clearDepth(1);
  gl.enable(gl.DEPTH_TEST);
  gl.depthFunc(gl.LESS);
  gl.disable(gl.CULL_FACE);
  gl.disable(gl.BLEND);
  gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
  const passes = gridMode > 0 && grid ? [] : scene.specular_fix ? [0, 1, 2] : [0];
  if (passes.length === 0) paintGrid(width, height);
  for (const pass of passes) {
    if (pass === 1) {
      gl.depthFunc(gl.EQUAL);
      gl.enable(gl.BLEND);
      gl.blendFunc(gl.DST_COLOR, gl.ZERO);
    } else if (pass === 2) {
      gl.blendFunc(gl.ONE, gl.ONE);
    }
    paint(pass, width, height);
  }
  gl.depthFunc(gl.LESS);
  gl.disable(gl.BLEND);
  paintRayTree(width, height);
  frames += 1;
  document.body.dataset.frame = String(frames);
  const now = performance.now();
  frameTimes.push(now);
  while (frameTimes.length > 0 && frameTimes[0] < now - 1000) frameTimes.shift();
}

function redraw() {
  if (!pending) {
    pending = true;
    requestAnimationFrame(draw);
  }
}

setInterval(() => {
  const now = performance.now();
  while (frameTimes.length > 0 && frameTimes[0] < now - 1000) frameTimes.shift();
  // The preview draws only when something changes: no frame in the last second is idle, not a
  // rate of 0.
  document.getElementById("fps").textContent = frameTimes.length ? String(frameTimes.length) : "idle";
}, 500);

// ---- The ray tree ('t'), drawn as the staff's RayTree::paint of assignment 5 ----
// Each kind of segment: its colour, and the segments as [from, to] pairs.
const TREE_COLOURS = {
  camera: [0.7, 0.7, 0.7],
  shadow: [0.1, 0.9, 0.1],
  reflected: [0.9, 0.1, 0.1],
  refracted: [0.1, 0.1, 0.9],
};
// Where a ray that hits nothing is drawn to, as the staff's Segment clamps it.
const MISS_LENGTH = 100;
let treeSegments = null;

// Every segment drawn, for clicks: its ends, and where the account tells of it (the node's
// number in the account's order, and the light for a shadow ray).
let treeLines = [];

// The segments of an -inspect tree: each ray from its start to its hit (or MISS_LENGTH along
// it), and each shadow ray sent from the hit toward its light.
function segmentsOf(tree) {
  const out = { camera: [], shadow: [], reflected: [], refracted: [] };
  treeLines = [];
  let nodes = 0;
  const visit = (node) => {
    const number = nodes++;
    if (!node.ray) return;
    const from = node.ray.origin, d = node.ray.direction;
    const t = node.hit ? node.hit.t : MISS_LENGTH / Math.hypot(d[0], d[1], d[2]);
    const segment = [from, add(from, scale(d, t))];
    (out[node.kind] || out.reflected).push(segment);
    treeLines.push({ segment, node: number, light: null });
    if (node.hit) {
      for (const light of node.lights || []) {
        if (light.shadow_ray !== "blocked" && light.shadow_ray !== "clear") continue;
        const reach = light.distance === "infinite" ? MISS_LENGTH : Math.min(light.distance, MISS_LENGTH);
        const shadow = [node.hit.point, add(node.hit.point, scale(light.to_light, reach))];
        out.shadow.push(shadow);
        treeLines.push({ segment: shadow, node: number, light: light.light });
      }
    }
    for (const child of node.children || []) visit(child);
  };
  visit(tree);
  return out;
}

// The account's line for a segment: its node's header (the n-th "... ray, weight" line), or
// within that node the line of its light.
function accountLine(lines, { node, light }) {
  const headers = [];
  lines.forEach((line, k) => { if (/^\s*\w+ ray, weight/.test(line)) headers.push(k); });
  const header = headers[node];
  if (header === undefined) return -1;
  if (light === null) return header;
  const pad = lines[header].match(/^\s*/)[0].length + 2;
  for (let k = header + 1; k < lines.length && !headers.includes(k); k++) {
    if (lines[k].startsWith(`${" ".repeat(pad)}light ${light} `)) return k;
  }
  return header;
}

function showAccount(text, highlighted) {
  const pre = document.getElementById("inspect");
  pre.replaceChildren();
  text.split("\n").forEach((line, k) => {
    const span = document.createElement("span");
    span.textContent = `${line}\n`;
    if (k === highlighted) span.className = "highlighted";
    pre.appendChild(span);
  });
  const marked = pre.querySelector(".highlighted");
  if (marked) marked.scrollIntoView({ block: "nearest" });
}

// A click on the canvas near a segment of the tree highlights its line in the account.
function pickSegment(x, y) {
  if (treeLines.length === 0) return;
  const m = matrices(canvas.width, canvas.height);
  const clip = (p) => [0, 1, 2, 3].map((r) => m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r]);
  const toScreen = (c) => [((c[0] / c[3] + 1) / 2) * canvas.width, ((1 - c[1] / c[3]) / 2) * canvas.height];
  // A segment that reaches behind the eye is cut where it passes the eye's plane.
  const NEAR_W = 1e-3;
  let best = null;
  for (const line of treeLines) {
    let [ca, cb] = line.segment.map(clip);
    if (ca[3] <= NEAR_W && cb[3] <= NEAR_W) continue;
    const cut = (from, to) => {
      const t = (from[3] - NEAR_W) / (from[3] - to[3]);
      return from.map((v, k) => v + t * (to[k] - v));
    };
    if (ca[3] <= NEAR_W) ca = cut(cb, ca);
    if (cb[3] <= NEAR_W) cb = cut(ca, cb);
    const [a, b] = [toScreen(ca), toScreen(cb)];
    const [dx, dy] = [b[0] - a[0], b[1] - a[1]];
    const along = Math.max(0, Math.min(1, ((x - a[0]) * dx + (y - a[1]) * dy) / (dx * dx + dy * dy || 1)));
    const distance = Math.hypot(a[0] + along * dx - x, a[1] + along * dy - y);
    if (distance <= 5 && (!best || distance < best.distance)) best = { line, distance };
  }
  if (!best) return;
  const text = document.getElementById("inspect").textContent;
  const lines = text.split("\n");
  const k = accountLine(lines, best.line);
  showAccount(text.replace(/\n$/, ""), k);
  document.body.dataset.highlighted = k >= 0 ? lines[k].trim() : "";
}

function paintRayTree(width, height) {
  if (!treeSegments) return;
  const l = lineProgram;
  gl.useProgram(l.program);
  gl.bindVertexArray(l.vertexArray);
  gl.uniformMatrix4fv(l.viewProjection, false, new Float32Array(matrices(width, height)));
  gl.bindBuffer(gl.ARRAY_BUFFER, l.lines);
  const draw = (alpha) => {
    for (const [kind, colour] of Object.entries(TREE_COLOURS)) {
      const segments = treeSegments[kind];
      if (segments.length === 0) continue;
      gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(segments.flat(2)), gl.DYNAMIC_DRAW);
      gl.uniform4f(l.colour, colour[0], colour[1], colour[2], alpha);
      gl.drawArrays(gl.LINES, 0, segments.length * 2);
    }
  };
  // Seen through the scene, faintly; then solid where nothing hides it.
  gl.disable(gl.DEPTH_TEST);
  gl.enable(gl.BLEND);
  gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
  draw(0.3);
  gl.disable(gl.BLEND);
  gl.enable(gl.DEPTH_TEST);
  draw(1.0);
}

// The pixel under the mouse as the staff's keyboard() maps it: j = height - row (not
// height - 1 - row), so the tree is that of the pixel a row above the mouse; the top row
// traces itself.
function pixelUnderMouse() {
  const width = canvas.width, height = canvas.height;
  const [x, row] = mouseAt || [width / 2, height / 2];
  const i = Math.min(width - 1, Math.max(0, Math.floor(x)));
  const j = Math.min(height - 1, Math.max(0, height - Math.floor(row)));
  return [i, j];
}

async function traceRay([i, j]) {
  await reportCamera();
  const status = document.getElementById("render-status");
  const answer = await fetch(withToken(`/api/raytree?x=${i}&y=${j}`));
  if (!answer.ok) {
    status.textContent = await answer.text();
    return;
  }
  const tree = await answer.json();
  treeSegments = segmentsOf(tree.tree);
  const text = await (await fetch(withToken(`/api/raytree?x=${i}&y=${j}&format=text`))).text();
  showAccount(text.replace(/\n$/, ""), -1);
  fresh("inspect");
  status.textContent = `ray tree of pixel (${i}, ${j})`;
  lastTraced = [i, j];
  gridWalk = grid ? await (await fetch(withToken(`/api/gridwalk?x=${i}&y=${j}`))).json() : null;
  document.body.dataset.tree = `${i},${j}`;
  redraw();
}

async function renderView() {
  await reportCamera();
  const status = document.getElementById("render-status");
  status.textContent = "rendering…";
  const answer = await fetch(withToken("/api/render"), { method: "POST" });
  if (!answer.ok) {
    status.textContent = await answer.text();
    return;
  }
  const image = document.getElementById("rendered");
  const url = URL.createObjectURL(await answer.blob());
  await new Promise((done) => { image.onload = done; image.src = url; });
  image.classList.add("shown");
  renders += 1;
  document.body.dataset.render = String(renders);
  status.textContent = `rendered in ${answer.headers.get("X-Render-Seconds")} s, the line's images written`;
  const stats = JSON.parse(answer.headers.get("X-Render-Stats") || "null");
  document.getElementById("stats").textContent = stats || "";
  fresh("rendered", "stats");
}
let renders = 0;

document.getElementById("rendered").addEventListener("click", (e) => {
  const image = e.target;
  const i = Math.floor((e.offsetX * image.naturalWidth) / image.clientWidth);
  const row = Math.floor((e.offsetY * image.naturalHeight) / image.clientHeight);
  traceRay([i, image.naturalHeight - 1 - row]);
});

// ---- The grid ('g', with -grid): its occupied cells, the cells the last tree walked, the
// faces those were entered by; the grid's box in white lines ----
const GRID_MODES = ["scene", "occupied cells", "cells the ray tree walked", "faces the ray tree entered"];
// The handout's gradient (and -visualize_grid's colours by count): white to red.
const GRADIENT = [[1, 1, 1], [0.75, 0.35, 1], [0.3, 0.35, 1], [0.2, 0.85, 0.95],
  [0.3, 0.9, 0.3], [1, 0.95, 0.25], [1, 0.6, 0.15], [1, 0.15, 0.1]];
let gridMode = 0;
let lastTraced = null;
let grid = null;
let gridWalk = null;
const solid = (() => {
  const program = gl.createProgram();
  gl.attachShader(program, compile(gl.VERTEX_SHADER, `#version 300 es
in vec3 position;
in vec3 colour;
uniform mat4 viewProjection;
out vec3 shade;
void main() { shade = colour; gl_Position = viewProjection * vec4(position, 1.0); }`));
  gl.attachShader(program, compile(gl.FRAGMENT_SHADER, `#version 300 es
precision highp float;
in vec3 shade;
out vec4 fragment;
void main() { fragment = vec4(shade, 1.0); }`));
  gl.linkProgram(program);
  const vertexArray = gl.createVertexArray();
  const buffer = gl.createBuffer();
  gl.bindVertexArray(vertexArray);
  gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
  for (const [name, offset] of [["position", 0], ["colour", 12]]) {
    const at = gl.getAttribLocation(program, name);
    gl.enableVertexAttribArray(at);
    gl.vertexAttribPointer(at, 3, gl.FLOAT, false, 24, offset);
  }
  return { program, vertexArray, buffer, viewProjection: gl.getUniformLocation(program, "viewProjection") };
})();

// A face lit as -visualize_grid lights its cubes: ambient plus each light's N.L, no shadows.
function litFace(colour, normal) {
  let light = scene.ambient.slice();
  for (const l of scene.lights) {
    const toLight = l.position[3] === 0 ? l.position.slice(0, 3) : normalize(l.position.slice(0, 3));
    const nl = Math.max(0, dot(normal, toLight));
    light = add(light, scale(l.colour, nl));
  }
  return colour.map((c, k) => Math.min(1, c * light[k]));
}

// The corners of cell (i, j, k).
function cellBox([i, j, k]) {
  const size = [0, 1, 2].map((a) => (grid.max[a] - grid.min[a]) / grid.cells[a]);
  const low = [0, 1, 2].map((a) => grid.min[a] + [i, j, k][a] * size[a]);
  return [low, add(low, size)];
}

// The face of a box on `axis` at its low (sign -1) or high (sign 1) side, as two triangles.
function boxFace([low, high], axis, sign, colour, out) {
  const u = (axis + 1) % 3, v = (axis + 2) % 3;
  const at = (a, b) => {
    const p = [0, 0, 0];
    p[axis] = sign < 0 ? low[axis] : high[axis];
    p[u] = a ? high[u] : low[u];
    p[v] = b ? high[v] : low[v];
    return p;
  };
  const normal = [0, 0, 0];
  normal[axis] = sign;
  const c = litFace(colour, normal);
  for (const corner of [at(0, 0), at(1, 0), at(1, 1), at(0, 0), at(1, 1), at(0, 1)]) out.push(...corner, ...c);
}

function gridTriangles() {
  const out = [];
  if (gridMode === 1) {
    for (const [i, j, k, , colour] of grid.occupied) {
      const box = cellBox([i, j, k]);
      for (let axis = 0; axis < 3; axis++) for (const sign of [-1, 1]) boxFace(box, axis, sign, colour, out);
    }
  } else if (gridWalk && gridMode >= 2) {
    const counts = new Map(grid.occupied.map(([i, j, k, count]) => [`${i},${j},${k}`, count]));
    for (const ray of gridWalk.rays) {
      ray.cells.forEach(([i, j, k, axis, sign], n) => {
        const box = cellBox([i, j, k]);
        if (gridMode === 2) {
          const count = counts.get(`${i},${j},${k}`) || 0;
          const colour = count > 0 ? GRADIENT[Math.min(count, 8) - 1] : [0.5, 0.5, 0.5];
          for (let a = 0; a < 3; a++) for (const s of [-1, 1]) boxFace(box, a, s, colour, out);
        } else {
          // The face it came in by, coloured by its order along the ray.
          const colour = GRADIENT[Math.min(7, Math.floor((n * 8) / Math.max(1, ray.cells.length)))];
          boxFace(box, axis, sign, colour, out);
        }
      });
    }
  }
  return out;
}

function paintGrid(width, height) {
  const viewProjection = new Float32Array(matrices(width, height));
  const triangles = gridTriangles();
  if (triangles.length > 0) {
    gl.useProgram(solid.program);
    gl.bindVertexArray(solid.vertexArray);
    gl.bindBuffer(gl.ARRAY_BUFFER, solid.buffer);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(triangles), gl.DYNAMIC_DRAW);
    gl.uniformMatrix4fv(solid.viewProjection, false, viewProjection);
    gl.drawArrays(gl.TRIANGLES, 0, triangles.length / 6);
  }
  // The grid's box, in white lines.
  const [a, b] = [grid.min, grid.max];
  const corner = (x, y, z) => [x ? b[0] : a[0], y ? b[1] : a[1], z ? b[2] : a[2]];
  const edges = [];
  for (let e = 0; e < 12; e++) {
    const axis = Math.floor(e / 4), s = e % 4;
    const p = [0, 0, 0], q = [0, 0, 0];
    const others = [0, 1, 2].filter((x) => x !== axis);
    p[others[0]] = q[others[0]] = s & 1;
    p[others[1]] = q[others[1]] = (s >> 1) & 1;
    q[axis] = 1;
    edges.push([corner(...p), corner(...q)]);
  }
  const l = lineProgram;
  gl.useProgram(l.program);
  gl.bindVertexArray(l.vertexArray);
  gl.uniformMatrix4fv(l.viewProjection, false, viewProjection);
  gl.bindBuffer(gl.ARRAY_BUFFER, l.lines);
  gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(edges.flat(2)), gl.DYNAMIC_DRAW);
  gl.uniform4f(l.colour, 1, 1, 1, 1);
  gl.drawArrays(gl.LINES, 0, 24);
}

async function cycleGrid() {
  const status = document.getElementById("render-status");
  if (grid === null) {
    grid = await (await fetch(withToken("/api/grid"))).json();
    if (grid === null) {
      grid = undefined;
    }
  }
  if (!grid) {
    status.textContent = "this line has no grid: 'g' needs -grid NX NY NZ";
    return;
  }
  if (!gridWalk && lastTraced) {
    gridWalk = await (await fetch(withToken(`/api/gridwalk?x=${lastTraced[0]}&y=${lastTraced[1]}`))).json();
  }
  gridMode = (gridMode + 1) % GRID_MODES.length;
  document.body.dataset.grid = GRID_MODES[gridMode];
  status.textContent = `showing: ${GRID_MODES[gridMode]}`;
  redraw();
}

// ---- The camera's report to raycast (GET /api/camera) ----
let reportTimer = null;
let reported = "";
function cameraMoved() {
  document.getElementById("camera").textContent = cameraText();
  redraw();
  clearTimeout(reportTimer);
  reportTimer = setTimeout(() => reportCamera().catch(() => {}), 50);
}

// Tells raycast the camera ('r' and 't' trace the view the page shows): nothing at the file's
// camera, which raycast then takes exactly from the file.
async function reportCamera() {
  const atFile = JSON.stringify(camera) === JSON.stringify(cameraFrom(fileCamera));
  const text = atFile ? "" : cameraText();
  if (text === reported) return;
  await fetch(withToken("/api/camera"), { method: "POST", body: text });
  reported = text;
}

// ---- Mouse and keys, as the staff's glCanvas ----
let dragging = -1, lastX = 0, lastY = 0;
let mouseAt = null;
canvas.addEventListener("mousemove", (e) => { mouseAt = [e.offsetX, e.offsetY]; });
canvas.addEventListener("contextmenu", (e) => e.preventDefault());
let pressedAt = null;
canvas.addEventListener("mouseup", (e) => {
  // A click without a drag: a segment of the ray tree under it?
  if (pressedAt && Math.hypot(e.offsetX - pressedAt[0], e.offsetY - pressedAt[1]) < 3) {
    pickSegment(e.offsetX, e.offsetY);
  }
  pressedAt = null;
});
canvas.addEventListener("mousedown", (e) => {
  pressedAt = [e.offsetX, e.offsetY];
  const bounds = canvas.getBoundingClientRect();
  // Shift-drag trucks, for a mouse (or a touchpad) without a middle button.
  dragging = e.button === 0 && e.shiftKey ? 1 : e.button;
  lastX = e.clientX - bounds.left;
  lastY = e.clientY - bounds.top;
  e.preventDefault();
});
window.addEventListener("mouseup", () => { dragging = -1; });
// As GLUT's motion callback, a drag goes on outside the canvas while the button is held.
window.addEventListener("mousemove", (e) => {
  if (dragging < 0 || !camera) return;
  const bounds = canvas.getBoundingClientRect();
  const x = e.clientX - bounds.left, y = e.clientY - bounds.top;
  if (dragging === 0) rotateCamera(0.005 * (lastX - x), 0.005 * (lastY - y));
  else if (dragging === 1) truck((lastX - x) * 0.05, (y - lastY) * 0.05);
  else if (dragging === 2) dolly((x - lastX) * 0.05);
  lastX = x;
  lastY = y;
  cameraMoved();
});
canvas.addEventListener("wheel", (e) => {
  if (!camera) return;
  e.preventDefault();
  dolly(-e.deltaY * 0.005);
  cameraMoved();
}, { passive: false });
const KEYS = {
  q: () => {
    fetch(withToken("/api/quit"), { method: "POST" }).catch(() => {});
    document.getElementById("status").textContent = "raycast was asked to quit";
  },
  v: () => {
    if (!fileCamera) return;
    camera = cameraFrom(fileCamera);
    cameraMoved();
  },
  r: () => renderView(),
  t: () => traceRay(pixelUnderMouse()),
  g: () => cycleGrid(),
};
// Keys with modifiers stay the browser's.
window.addEventListener("keydown", (e) => {
  if (e.ctrlKey || e.metaKey || e.altKey) return;
  const key = KEYS[e.key.toLowerCase()];
  if (key && camera) key();
});
for (const name of Object.keys(KEYS)) {
  document.getElementById(`key-${name}`).addEventListener("click", () => { if (camera) KEYS[name](); });
}

// ---- The scene, and its changes ----
async function load() {
  const answer = await (await fetch(withToken("/api/scene"))).json();
  const error = document.getElementById("error");
  error.textContent = answer.error || "";
  error.classList.toggle("shown", Boolean(answer.error));
  if (!answer.scene || answer.version === version) return;
  const bytes = await (await fetch(withToken("/api/geometry"))).arrayBuffer();
  const first = scene === null;
  scene = answer.scene;
  version = answer.version;
  gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
  gl.bufferData(gl.ARRAY_BUFFER, bytes, gl.STATIC_DRAW);
  canvas.width = scene.width;
  canvas.height = scene.height;
  canvas.style.width = `${scene.width}px`;
  canvas.style.height = `${scene.height}px`;
  document.getElementById("name").textContent = scene.name || "raycast preview";
  document.getElementById("triangles").textContent = String(scene.triangles);
  const fileChanged = JSON.stringify(fileCamera) !== JSON.stringify(scene.camera);
  fileCamera = scene.camera;
  // A new camera in the file takes over; otherwise the view stays where the mouse left it.
  if (first || fileChanged) camera = cameraFrom(fileCamera);
  // With -visualize_grid the preview starts on the grid's occupied cells.
  if (first && scene.visualize_grid) await cycleGrid();
  if (!first) markStale();
  cameraMoved();
}

// After the scene changed, a render, its statistics and a ray tree are of the old scene: they
// stay to compare with, marked stale, and the tree drawn over the preview goes.
function markStale() {
  let stale = false;
  const rendered = document.getElementById("rendered");
  if (rendered.classList.contains("shown")) {
    rendered.classList.add("stale");
    stale = true;
  }
  for (const id of ["stats", "inspect"]) {
    const element = document.getElementById(id);
    if (element.textContent) {
      element.classList.add("stale");
      stale = true;
    }
  }
  if (treeSegments) {
    treeSegments = null;
    gridWalk = null;
    delete document.body.dataset.tree;
    stale = true;
  }
  if (stale) {
    document.getElementById("render-status").textContent =
      "stale: the scene changed since; press r to render it again, t for a ray tree";
    document.body.dataset.stale = "1";
  }
}

function fresh(...ids) {
  for (const id of ids) document.getElementById(id).classList.remove("stale");
  if (!document.querySelector(".stale")) delete document.body.dataset.stale;
}

let loading = Promise.resolve();
function reload() {
  loading = loading.then(load).catch((e) => {
    document.getElementById("status").textContent = `cannot load the scene: ${e}`;
  });
}

function listen() {
  const status = document.getElementById("status");
  const events = new EventSource(withToken("/api/events"));
  events.addEventListener("progress", (e) => {
    const status = document.getElementById("render-status");
    if (status.textContent.startsWith("rendering")) status.textContent = `rendering… ${e.data}%`;
  });
  events.addEventListener("scene", () => {
    status.textContent = "connected";
    status.classList.remove("lost");
    reload();
  });
  // EventSource tries again by itself: a raycast started again on this port (with the same
  // token) is found without reloading the page.
  events.onerror = () => {
    status.textContent = "lost: waiting for raycast";
    status.classList.add("lost");
  };
}

reload();
listen();
