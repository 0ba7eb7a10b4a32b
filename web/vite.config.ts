import { defineConfig } from 'vitest/config';

// The C++ server (`trailscope serve`) serves web/dist at `/`, on the same origin as the API.
// In development, `npm run dev` proxies the API, the tiles and the job WebSocket to a local server.
const backend = process.env.TRAILSCOPE_BACKEND ?? 'http://127.0.0.1:8080';

export default defineConfig({
  base: '/',
  build: {
    outDir: 'dist',
    emptyOutDir: true,
    sourcemap: true,
    chunkSizeWarningLimit: 1500,
  },
  server: {
    proxy: {
      '/api/v1/ws': { target: backend, ws: true, changeOrigin: true },
      // Replay viewers: /api/v1/replays/{id}/ws (and the replay routes themselves).
      '/api/v1/replays': { target: backend, ws: true, changeOrigin: true },
      '/api': { target: backend, changeOrigin: true },
      '/tiles': { target: backend, changeOrigin: true },
    },
  },
  test: {
    // TRAILSCOPE_E2E=1: the checks against a running server (src/**/*.e2e.ts, run by tests/e2e/run.sh).
    include: process.env.TRAILSCOPE_E2E ? ['src/**/*.e2e.ts'] : ['src/**/*.test.ts'],
    environment: 'node',
  },
});
