// The explorer's picture (sunset/explorer/widget.py, PictureView): draws the RGBA bytes that Python rendered
// into a canvas, unchanged (putImageData: no image decoder, no colour management), and reports the pixel under
// the pointer, whose meaning Python writes back as `readout` (sunset/explorer/picture.py, readout).
// Plain JavaScript, no network: anywidget's JupyterLab extension loads it from the widget's state.

function render({ model, el }) {
  const box = document.createElement("div");
  box.className = "sunset-explorer";
  const canvas = document.createElement("canvas");
  canvas.className = "sunset-explorer-picture";
  canvas.style.imageRendering = "pixelated";
  canvas.style.cursor = "crosshair";
  canvas.style.display = "block";
  const readout = document.createElement("pre");
  readout.className = "sunset-explorer-readout";
  readout.style.whiteSpace = "pre-wrap";
  readout.style.margin = "0.3em 0";
  readout.style.minHeight = "3.9em";
  box.append(canvas, readout);
  el.append(box);

  function show() {
    const w = model.get("width"), h = model.get("height");
    const bytes = model.get("rgba");       // a DataView of rows of RGBA bytes
    canvas.style.width = w + "px";
    box.style.width = w + "px";
    if (!bytes || bytes.byteLength !== 4 * w * h) return;
    if (canvas.width !== w || canvas.height !== h) {
      canvas.width = w;
      canvas.height = h;
    }
    const pixels = new Uint8ClampedArray(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    canvas.getContext("2d").putImageData(new ImageData(new Uint8ClampedArray(pixels), w, h), 0, 0);
  }
  function numbered() {
    canvas.dataset.serial = String(model.get("serial"));   // which picture is shown (the browser check reads it)
  }
  function said() {
    readout.textContent = model.get("readout");
  }

  let last = "";
  function point(pixel) {
    const key = pixel.join(",");
    if (key === last) return;         // a message only when the pointer reaches another pixel
    last = key;
    model.set("pointer", pixel);
    model.save_changes();
  }
  canvas.addEventListener("pointermove", (e) => {
    const rect = canvas.getBoundingClientRect();
    const w = canvas.width, h = canvas.height;
    const x = Math.floor((e.clientX - rect.left) / rect.width * w);
    const y = Math.floor((e.clientY - rect.top) / rect.height * h);
    point(x >= 0 && x < w && y >= 0 && y < h ? [x, y] : []);
  });
  canvas.addEventListener("pointerleave", () => point([]));

  model.on("change:rgba", show);
  model.on("change:serial", numbered);
  model.on("change:readout", said);
  show();
  numbered();
  said();
}

export default { render };
