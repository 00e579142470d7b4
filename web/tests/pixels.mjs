// Pixel statistics of the page's WebGL canvas (drawn with preserveDrawingBuffer).
export async function canvasColours(page) {
  return page.evaluate(() => {
    const src = document.getElementById('vfsd-canvas');
    const c = document.createElement('canvas');
    c.width = src.width;
    c.height = src.height;
    const g = c.getContext('2d');
    g.drawImage(src, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    let blue = 0, red = 0;
    const seen = new Set();
    for (let i = 0; i < d.length; i += 4) {
      const [r, gr, b] = [d[i], d[i + 1], d[i + 2]];
      if (b > 120 && b > r + 60 && b > gr + 40) blue++;
      if (r > 120 && r > b + 60 && r > gr + 60) red++;
      seen.add((r >> 3) << 10 | (gr >> 3) << 5 | (b >> 3));
    }
    return { blue, red, distinct: seen.size };
  });
}
