/* The sunset colour-table player: the Dicomed D-48 in the browser.
 *
 * Everything it shows was computed in Python (sunset/recorder/player.py): the
 * codes of one wave cycle, the three 256-entry tables of every grid hour, and
 * the sun's disk on the picture at that hour. This script only looks entries
 * up and composes them, exactly as sunset.expose does:
 *
 *   1. three passes: pixel = (red[code], green[code], blue[code]) of the hour;
 *   2. the sun-disk rule: a pixel of the sun's box with coverage k/s^2 > 0 and
 *      a sky code (sky, track or halo) becomes (1 - w) * entry + w * sun, mixed
 *      in linear light (the exported decode table) and rounded back to a byte
 *      through the exported thresholds (byte = how many thresholds are <= x).
 *
 * Test hook: ?frame=F&hours=H&dump=1 draws frame F with the table of the grid
 * hour nearest H and writes canvas.toDataURL("image/png") into #sunset-dump.
 * Plain JavaScript, no libraries, nothing loaded from anywhere.
 */
(function () {
  "use strict";
  const root = document.getElementById("sunset-player");
  if (!root || root.dataset.started) return;
  root.dataset.started = "1";
  const role = (name) => root.querySelector('[data-role="' + name + '"]');
  const roles = (name) => Array.from(root.querySelectorAll('[data-role="' + name + '"]'));
  const data = JSON.parse(document.getElementById("sunset-player-data").textContent);

  const W = data.width, H = data.height, N = data.frames, M = data.hours.length, P = W * H;
  const FILM = data.cycles * N;                 // film frames over the whole range of hours
  const n2 = data.supersample * data.supersample;
  const skyStart = data.sky_start;
  const decodeLut = Float64Array.from(data.decode);
  const thresholds = Float64Array.from(data.encode);

  function bytes(b64) {
    const s = atob(b64);
    const out = new Uint8Array(s.length);
    for (let i = 0; i < s.length; i++) out[i] = s.charCodeAt(i);
    return out;
  }
  const tables = bytes(data.tables);            // M x 3 x 256: red, green, blue tables of each grid hour

  // The tables of one grid hour as packed RGBA words, built on first use.
  const luts = new Array(M);
  function lut(h) {
    if (!luts[h]) {
      const rgba = new Uint8Array(1024);
      const t = h * 768;
      for (let c = 0; c < 256; c++) {
        rgba[4 * c] = tables[t + c];
        rgba[4 * c + 1] = tables[t + 256 + c];
        rgba[4 * c + 2] = tables[t + 512 + c];
        rgba[4 * c + 3] = 255;
      }
      luts[h] = new Uint32Array(rgba.buffer);
    }
    return luts[h];
  }

  // Linear value -> byte, as sunset.expose rounds it: the number of thresholds <= x.
  function quantise(x) {
    let lo = 0, hi = thresholds.length;
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (thresholds[mid] <= x) lo = mid + 1; else hi = mid;
    }
    return lo;
  }

  function nearestHour(hours) {
    let best = 0;
    for (let i = 1; i < M; i++) {
      if (Math.abs(data.hours[i] - hours) < Math.abs(data.hours[best] - hours)) best = i;
    }
    return best;
  }

  // ----------------------------------------------------------------- canvases
  const picture = role("picture");
  picture.width = W;
  picture.height = H;
  const ctx = picture.getContext("2d");
  const image = ctx.createImageData(W, H);
  const out8 = image.data;
  const out32 = new Uint32Array(out8.buffer);
  const passCanvas = [0, 1, 2].map((k) => role("pass-" + k));
  passCanvas.forEach((c) => { c.width = W; c.height = H; });
  const passImage = [0, 1, 2].map(() => {
    const img = ctx.createImageData(W, H);
    for (let i = 3; i < img.data.length; i += 4) img.data[i] = 255;
    return img;
  });
  const strip = role("strip");
  const stripCtx = strip.getContext("2d");

  let codes = null;                              // one Uint8Array per frame
  const state = {frame: 0, hour: 0, playing: false, follow: false, view: "film", filmPos: 0, hover: null};

  // ----------------------------------------------------------------- composing
  function compose(f, h) {
    const c = codes[f], L = lut(h);
    for (let i = 0; i < P; i++) out32[i] = L[c[i]];
    const s = data.sun[h];
    if (s) {
      const t = h * 768, col = s.colour;
      for (let r = 0; r < s.h; r++) {
        for (let q = 0; q < s.w; q++) {
          const k = s.cover[r * s.w + q];
          if (k === 0) continue;
          const i = (s.r0 + r) * W + s.c0 + q;
          const code = c[i];
          if (code < skyStart) continue;  // the disk only where rays reach the sky
          const w = k / n2;
          for (let ch = 0; ch < 3; ch++) {
            const entry = decodeLut[tables[t + ch * 256 + code]];
            out8[4 * i + ch] = quantise((1 - w) * entry + w * col[ch]);
          }
        }
      }
    }
  }

  function showPass(k, canvasCtx) {
    const p = passImage[k].data;
    for (let i = k; i < out8.length; i += 4) p[i] = out8[i];
    canvasCtx.putImageData(passImage[k], 0, 0);
  }

  function draw() {
    compose(state.frame, state.hour);
    if (state.view === "film" || state.view === "passes") ctx.putImageData(image, 0, 0);
    else showPass(Number(state.view), ctx);
    if (state.view === "passes") passCanvas.forEach((c, k) => showPass(k, c.getContext("2d")));
    showLabels();
    inspect();
  }

  // ----------------------------------------------------------------- the table strip and the inspector
  const stripImage = stripCtx.createImageData(strip.width, strip.height);
  let stripHour = -1;
  const ROWS = [[0, 24, -1], [27, 35, 0], [36, 44, 1], [45, 53, 2]];   // then the group names below   // y0, y1, pass (-1: all three)
  function drawStrip(code) {
    const SW = strip.width, SH = strip.height, per = SW / 256;
    if (stripHour !== state.hour) {
      const t = state.hour * 768, d = stripImage.data;
      d.fill(255);
      for (const [y0, y1, k] of ROWS) {
        for (let y = y0; y < y1; y++) {
          for (let x = 0; x < SW; x++) {
            const c = Math.min(255, Math.floor(x / per)), o = 4 * (y * SW + x);
            for (let ch = 0; ch < 3; ch++) d[o + ch] = (k < 0 || k === ch) ? tables[t + ch * 256 + c] : 0;
          }
        }
      }
      for (const g of data.groups) {              // a tick where each group starts
        const x = Math.round(g.first * per);
        for (let y = 53; y < SH; y++) { const o = 4 * (y * SW + x); d[o] = d[o + 1] = d[o + 2] = 0; }
      }
      stripHour = state.hour;
    }
    stripCtx.putImageData(stripImage, 0, 0);
    stripCtx.fillStyle = "#000";
    stripCtx.font = "11px sans-serif";
    for (const g of data.groups) stripCtx.fillText(g.name, Math.round(g.first * per) + 3, SH - 3);
    if (code !== null) {
      const x = code * per;
      stripCtx.lineWidth = 2;
      stripCtx.strokeStyle = "#fff";
      stripCtx.strokeRect(x - 2, 1, per + 4, SH - 2);
      stripCtx.strokeStyle = "#000";
      stripCtx.strokeRect(x - 4, 0, per + 8, SH);
    }
  }

  function groupOf(code) {
    for (const g of data.groups) if (code >= g.first && code <= g.last) return g;
    return null;
  }

  function inspect() {
    const box = role("inspect");
    if (!state.hover || !codes) { drawStrip(null); return; }
    const [x, y] = state.hover, i = y * W + x;
    const code = codes[state.frame][i], g = groupOf(code), t = state.hour * 768;
    const entry = [0, 1, 2].map((ch) => tables[t + ch * 256 + code]);
    const drawn = [out8[4 * i], out8[4 * i + 1], out8[4 * i + 2]];
    let sunNote = "";
    const s = data.sun[state.hour];
    if (s && y >= s.r0 && y < s.r0 + s.h && x >= s.c0 && x < s.c0 + s.w) {
      const k = s.cover[(y - s.r0) * s.w + (x - s.c0)];
      if (k > 0) {
        sunNote = code >= skyStart
          ? " In the sun's disk: " + k + "/" + n2 + " of the pixel covered, drawn (" + drawn.join(", ") + ")."
          : " Behind the sun's disk, but not a sky code: the disk is not drawn here.";
      }
    }
    box.textContent = "";
    const line = (text, bold) => {
      const e = document.createElement(bold ? "b" : "span");
      e.textContent = text;
      box.appendChild(e);
    };
    line("pixel (" + x + ", " + y + "): code " + code + ", ", false);
    line(g ? g.label : "?", true);
    line(" (codes " + (g ? g.first + "-" + g.last : "?") + ")", false);
    box.appendChild(document.createElement("br"));
    line(data.meanings[code], false);
    box.appendChild(document.createElement("br"));
    line("table entry at this hour: red " + entry[0] + ", green " + entry[1] + ", blue " + entry[2] + "." + sunNote,
         false);
    drawStrip(code);
  }

  function showLabels() {
    const h = data.hours[state.hour], e = data.elevation[state.hour];
    role("frame-label").textContent = "frame " + state.frame + " of " + N + ": t = " +
      data.times[state.frame].toFixed(3) + " s" + (data.period ? " of T = " + data.period.toFixed(3) + " s" : "");
    role("hours-label").textContent = (h >= 0 ? h.toFixed(3) + " h before sunset" : (-h).toFixed(3) +
      " h after sunset") + ", the sun's centre " + e.toFixed(2) + "\u00b0 " + (e >= 0 ? "up" : "down");
    role("frame").value = String(state.frame);
    role("hours").value = String(state.hour);
  }

  // ----------------------------------------------------------------- playing
  let last = null, pending = 0;
  function hourAt(pos) {
    return FILM > 1 && M > 1 ? Math.round(pos * (M - 1) / (FILM - 1)) : 0;
  }
  function tick(now) {
    if (!state.playing) { last = null; return; }
    if (last !== null) pending += now - last;
    last = now;
    const step = 1000 / data.fps;
    if (pending >= step) {
      const n = Math.floor(pending / step);
      pending -= n * step;
      if (pending > step) pending = 0;           // after a long stall, do not race to catch up
      state.frame = (state.frame + n) % N;
      if (state.follow) {
        state.filmPos = (state.filmPos + n) % FILM;
        state.hour = hourAt(state.filmPos);
      }
      draw();
    }
    requestAnimationFrame(tick);
  }
  function play() {
    if (state.playing || !codes) return;
    state.playing = true;
    role("play").textContent = "pause";
    requestAnimationFrame(tick);
  }
  function pause() {
    state.playing = false;
    role("play").textContent = "play";
  }

  // ----------------------------------------------------------------- controls
  function wire() {
    const frame = role("frame"), hours = role("hours");
    frame.max = String(N - 1);
    hours.max = String(M - 1);
    role("play").addEventListener("click", () => (state.playing ? pause() : play()));
    frame.addEventListener("input", () => { state.frame = Number(frame.value); draw(); });
    hours.addEventListener("input", () => {
      state.hour = Number(hours.value);
      state.filmPos = M > 1 ? Math.round(state.hour * (FILM - 1) / (M - 1)) : 0;
      draw();
    });
    role("follow").addEventListener("change", (e) => {
      state.follow = e.target.checked;
      state.filmPos = M > 1 ? Math.round(state.hour * (FILM - 1) / (M - 1)) : 0;
    });
    roles("view").forEach((r) => r.addEventListener("change", () => {
      if (!r.checked) return;
      state.view = r.value;
      role("passes").hidden = state.view !== "passes";
      draw();
    }));
    const where = (e) => {
      const rect = picture.getBoundingClientRect();
      const x = Math.floor((e.clientX - rect.left) / rect.width * W);
      const y = Math.floor((e.clientY - rect.top) / rect.height * H);
      return x >= 0 && x < W && y >= 0 && y < H ? [x, y] : null;
    };
    picture.addEventListener("pointermove", (e) => { state.hover = where(e); inspect(); });
    picture.addEventListener("pointerleave", () => { state.hover = null; inspect(); });
  }

  // ----------------------------------------------------------------- the codes: lossless 8-bit PNG frames
  // Decoded here rather than through a canvas, so that no colour management and no canvas read-back
  // (which some browsers add noise to, against fingerprinting) can touch a code: the PNG's zlib stream
  // is inflated by the browser's DecompressionStream and its row filters are undone below.
  async function inflate(chunks) {
    const stream = new Blob(chunks).stream().pipeThrough(new DecompressionStream("deflate"));
    return new Uint8Array(await new Response(stream).arrayBuffer());
  }

  async function decodePng(png) {
    const view = new DataView(png.buffer, png.byteOffset, png.byteLength);
    const idat = [];
    let pos = 8;                                   // after the signature
    while (pos + 8 <= png.length) {
      const len = view.getUint32(pos);
      const type = String.fromCharCode(png[pos + 4], png[pos + 5], png[pos + 6], png[pos + 7]);
      if (type === "IHDR") {
        const [w, h] = [view.getUint32(pos + 8), view.getUint32(pos + 12)];
        const depth = png[pos + 16], colour = png[pos + 17], interlace = png[pos + 20];
        if (w !== W || h !== H || depth !== 8 || colour !== 0 || interlace !== 0) {
          throw new Error("a frame of codes is not an 8-bit greyscale PNG of " + W + " x " + H);
        }
      } else if (type === "IDAT") {
        idat.push(png.subarray(pos + 8, pos + 8 + len));
      } else if (type === "IEND") {
        break;
      }
      pos += 12 + len;
    }
    const raw = await inflate(idat);
    if (raw.length !== H * (W + 1)) throw new Error("a frame of codes has the wrong length");
    const out = new Uint8Array(P);
    for (let y = 0; y < H; y++) {
      const filter = raw[y * (W + 1)], first = y * (W + 1) + 1, row = y * W, up = row - W;
      for (let x = 0; x < W; x++) {
        const a = x > 0 ? out[row + x - 1] : 0;
        const b = y > 0 ? out[up + x] : 0;
        const c = x > 0 && y > 0 ? out[up + x - 1] : 0;
        let v = raw[first + x];
        if (filter === 1) v += a;
        else if (filter === 2) v += b;
        else if (filter === 3) v += (a + b) >> 1;
        else if (filter === 4) {
          const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
          v += pa <= pb && pa <= pc ? a : (pb <= pc ? b : c);
        } else if (filter !== 0) throw new Error("unknown PNG filter " + filter);
        out[row + x] = v & 255;
      }
    }
    return out;
  }

  function decodeFrames() {
    return Promise.all(data.codes.map((b64) => decodePng(bytes(b64))));
  }

  const query = new URLSearchParams(window.location.search);
  const dump = query.get("dump") === "1";
  if (query.has("frame")) {
    const f = Number.parseInt(query.get("frame"), 10);
    if (Number.isFinite(f)) state.frame = ((f % N) + N) % N;
  }
  const asked = query.has("hours") ? Number.parseFloat(query.get("hours")) : data.start_hours;
  state.hour = Number.isFinite(asked) ? nearestHour(asked) : 0;
  state.filmPos = M > 1 ? Math.round(state.hour * (FILM - 1) / (M - 1)) : 0;

  const ready = decodeFrames().then((frames) => {
    codes = frames;
    wire();
    draw();
    if (dump) document.getElementById("sunset-dump").textContent = picture.toDataURL("image/png");
    root.dataset.state = "ready";
    if (!dump && !query.has("frame")) play();
  }).catch((err) => {
    root.dataset.state = "error";
    role("message").textContent = "The player could not start: " + err;
    throw err;
  });

  // For the browser check and the benchmark.
  window.sunsetPlayer = {
    ready,
    state,
    play,
    pause,
    draw(f, h) { state.frame = f; state.hour = h; draw(); },
    nearestHour,
    /* Decode a base64 8-bit greyscale PNG of the player's size, as the frames are decoded: an array of codes. */
    decodePng: (b64) => decodePng(bytes(b64)).then((codes) => Array.from(codes)),
    /* Time `count` blocks of ten draws (compose + putImageData) of varying frames and hours:
       the milliseconds per draw in each block (a block beats the timer's coarse resolution). */
    bench(count) {
      for (let h = 0; h < M; h++) lut(h);
      const times = [];
      let i = 0;
      for (let b = 0; b < count; b++) {
        const t0 = performance.now();
        for (let j = 0; j < 10; j++, i++) {
          compose(i % N, (i * 7) % M);
          ctx.putImageData(image, 0, 0);
        }
        times.push((performance.now() - t0) / 10);
      }
      draw();
      return times;
    },
  };
})();
