// The plot box of a 2D canvas (inside its padding) and where a click falls in it.

export function plotBox(canvas, pad) {
  const { width, height } = canvas;
  return { x0: pad.left, y0: pad.top, w: width - pad.left - pad.right, h: height - pad.top - pad.bottom };
}

// The click's position in the canvas's own pixels, or null outside the box.
export function clickIn(canvas, event, box) {
  const rect = canvas.getBoundingClientRect();
  const px = ((event.clientX - rect.left) * canvas.width) / rect.width;
  const py = ((event.clientY - rect.top) * canvas.height) / rect.height;
  if (px < box.x0 || px >= box.x0 + box.w || py < box.y0 || py >= box.y0 + box.h) return null;
  return [px, py];
}
