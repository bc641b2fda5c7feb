// Drives raycast's preview in headless Chromium for tests/preview.rs and the preview bench.
//   node drive.mjs SCRIPT.json
// SCRIPT: { "url": ..., "steps": [ ... ] }, each step one of
//   { "canvas": "OUT.png" }                 the canvas's pixels, as a PNG file
//   { "drag": [button, [x0, y0], [x1, y1], steps] }   a drag on the canvas (button 0, 1, 2)
//   { "key": "q" }                          a key press
//   { "move": [x, y] }                      the mouse to that point of the canvas
//   { "click_eval": "expression" }          a click at the [x, y] of the canvas it gives
//   { "wait_frame_after": N }               until more than N frames were drawn
//   { "wait_text": [selector, text] }       until the element's text contains text
//   { "wait_ms": N }
//   { "save": [path, text] }                the file saved as an editor saves it (rename)
//   { "wait_eval": "expression" }           until it is true; ms since the last save
//   { "eval": "expression" }                its value goes to the report
//   { "fps": [steps, pixels] }              a left drag of `steps` moves of `pixels`: frames/s
// Prints a JSON report: what each step measured, and the page's console errors.
import { chromium } from "playwright-core";
import { readFileSync, renameSync, writeFileSync } from "node:fs";

const script = JSON.parse(readFileSync(process.argv[2], "utf8"));
const browser = await chromium.launch({
  executablePath: process.env.RAYCAST_CHROMIUM || "/usr/bin/chromium",
  args: [
    "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
    "--ignore-gpu-blocklist", "--disable-background-networking", "--disable-component-update",
    "--disable-sync", "--no-first-run", "--disable-quic",
  ],
});
const report = { steps: [], console: [] };
let saved = Date.now();
// After 'q' raycast is gone: the page's attempts to reach it are not errors of the page.
let quitting = false;
try {
  const page = await browser.newPage({ deviceScaleFactor: 1, viewport: { width: 1000, height: 800 } });
  page.on("console", (m) => { if (m.type() === "error" && !quitting) report.console.push(m.text()); });
  page.on("pageerror", (e) => report.console.push(String(e)));
  const loadStart = Date.now();
  await page.goto(script.url);
  await page.waitForFunction(() => Number(document.body.dataset.frame || 0) >= 1, null, { timeout: 20000 });
  report.first_frame_ms = Date.now() - loadStart;
  const frame = () => page.evaluate(() => Number(document.body.dataset.frame || 0));
  const box = await page.locator("#preview").boundingBox();
  for (const step of script.steps) {
    if (step.canvas) {
      const url = await page.evaluate(() => document.getElementById("preview").toDataURL("image/png"));
      writeFileSync(step.canvas, Buffer.from(url.split(",")[1], "base64"));
      report.steps.push({ canvas: step.canvas });
    } else if (step.drag) {
      const [button, [x0, y0], [x1, y1], steps] = step.drag;
      const name = ["left", "middle", "right"][button];
      const before = await frame();
      await page.mouse.move(box.x + x0, box.y + y0);
      await page.mouse.down({ button: name });
      await page.mouse.move(box.x + x1, box.y + y1, { steps: steps || 10 });
      await page.mouse.up({ button: name });
      await page.waitForFunction((n) => Number(document.body.dataset.frame) > n, before, { timeout: 10000 });
      // Let the camera's report reach raycast.
      await page.waitForTimeout(300);
      report.steps.push({ drag: step.drag });
    } else if (step.click_eval) {
      // A click where the page's expression says (canvas pixels).
      const [x, y] = await page.evaluate(step.click_eval);
      await page.mouse.click(box.x + x, box.y + y);
      report.steps.push({ click: [x, y] });
    } else if (step.move) {
      const [x, y] = step.move;
      await page.mouse.move(box.x + x, box.y + y);
      report.steps.push({ move: step.move });
    } else if (step.key) {
      quitting ||= step.key === "q";
      await page.keyboard.press(step.key);
      report.steps.push({ key: step.key });
    } else if (step.wait_frame_after !== undefined) {
      await page.waitForFunction((n) => Number(document.body.dataset.frame) > n, step.wait_frame_after, { timeout: 10000 });
      report.steps.push({ frame: await frame() });
    } else if (step.wait_text) {
      const [selector, text] = step.wait_text;
      const start = Date.now();
      await page.waitForFunction(([s, t]) => (document.querySelector(s)?.textContent || "").includes(t), [selector, text], { timeout: 10000 });
      report.steps.push({ wait_text: step.wait_text, ms: Date.now() - start });
    } else if (step.save) {
      // As an editor saves: the new text written beside the file, then renamed over it.
      const [path, text] = step.save;
      writeFileSync(`${path}.saving`, text);
      renameSync(`${path}.saving`, path);
      saved = Date.now();
      report.steps.push({ save: path });
    } else if (step.wait_eval) {
      await page.waitForFunction(step.wait_eval, null, { timeout: 10000 });
      report.steps.push({ wait_eval: step.wait_eval, ms: Date.now() - saved });
    } else if (step.wait_ms) {
      await page.waitForTimeout(step.wait_ms);
    } else if (step.eval) {
      report.steps.push({ eval: step.eval, value: await page.evaluate(step.eval) });
    } else if (step.fps) {
      // A left drag of `steps` moves, sent as fast as the browser takes them (moves that come
      // faster than frames are drawn fold into one frame, as they would under a real mouse):
      // frames drawn (each a changed canvas: every frame follows a camera move) over the time
      // from the first move to the last frame.
      const [steps, pixels] = step.fps;
      const x0 = box.x + box.width / 4, y0 = box.y + box.height / 2;
      await page.mouse.move(x0, y0);
      await page.mouse.down({ button: "left" });
      const before = await frame();
      const start = Date.now();
      for (let i = 0; i < steps; i++) await page.mouse.move(x0 + (i + 1) * pixels, y0);
      await page.mouse.up({ button: "left" });
      // The last move's frame: drawn once nothing is pending.
      await page.waitForFunction(() => !pending, null, { timeout: 10000 });
      const seconds = (Date.now() - start) / 1000;
      const drawn = (await frame()) - before;
      report.steps.push({ fps: drawn / seconds, frames: drawn, seconds });
    }
  }
} finally {
  await browser.close();
}
console.log(JSON.stringify(report));
