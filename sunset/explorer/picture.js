// The explorer's picture (sunset/explorer/widget.py, PictureView): shows the PNG that Python rendered and
// reports the pixel under the pointer, whose meaning Python writes back as `readout`
// (sunset/explorer/picture.py, readout). Plain JavaScript, no network: anywidget's JupyterLab extension
// loads it from the widget's state.

function render({ model, el }) {
  const box = document.createElement("div");
  box.className = "sunset-explorer";
  const img = document.createElement("img");
  img.className = "sunset-explorer-picture";
  img.alt = "the explorer's picture";
  img.style.imageRendering = "pixelated";
  img.style.cursor = "crosshair";
  img.style.display = "block";
  const readout = document.createElement("pre");
  readout.className = "sunset-explorer-readout";
  readout.style.whiteSpace = "pre-wrap";
  readout.style.margin = "0.3em 0";
  readout.style.minHeight = "3.9em";
  box.append(img, readout);
  el.append(box);

  let url = null;
  function show() {
    const png = model.get("png");
    const width = model.get("width");
    img.style.width = width + "px";
    box.style.width = width + "px";
    if (!png || png.byteLength === 0) return;
    const next = URL.createObjectURL(new Blob([png], { type: "image/png" }));
    img.src = next;
    if (url) URL.revokeObjectURL(url);
    url = next;
  }
  function numbered() {
    img.dataset.serial = String(model.get("serial"));   // which render the picture is (the browser check reads it)
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
  img.addEventListener("pointermove", (e) => {
    const rect = img.getBoundingClientRect();
    const w = img.naturalWidth || model.get("width"), h = img.naturalHeight || model.get("height");
    const x = Math.floor((e.clientX - rect.left) / rect.width * w);
    const y = Math.floor((e.clientY - rect.top) / rect.height * h);
    point(x >= 0 && x < w && y >= 0 && y < h ? [x, y] : []);
  });
  img.addEventListener("pointerleave", () => point([]));

  model.on("change:png", show);
  model.on("change:serial", numbered);
  model.on("change:readout", said);
  show();
  numbered();
  said();
  return () => {
    if (url) URL.revokeObjectURL(url);
  };
}

export default { render };
