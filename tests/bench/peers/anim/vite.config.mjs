// Builds the animation benchmark page (index.html + main.js) into tests/bench/out/anim-page with the web
// app's Vite: the page imports the app's animation layer from web/src and deck.gl from tests/bench/peers.
//   web/node_modules/.bin/vite build --config tests/bench/peers/anim/vite.config.mjs
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const root = path.resolve(here, '../../../..');
export default {
  root: here,
  base: './',
  logLevel: 'warn',
  resolve: {
    // One MapLibre for the page, the app's module and deck.gl's overlay.
    alias: [{ find: /^maplibre-gl(\/.*)?$/, replacement: path.join(root, 'web/node_modules/maplibre-gl') + '$1' }],
  },
  build: {
    outDir: process.env.ANIM_PAGE_OUT ?? path.join(root, 'tests/bench/out/anim-page'),
    emptyOutDir: true,
    chunkSizeWarningLimit: 4000,
  },
};
