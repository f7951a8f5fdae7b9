/// <reference types="vitest" />
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { dirname, join } from "node:path";
import { defineConfig, type Plugin } from "vite";
import react from "@vitejs/plugin-react";

// The server to develop against (`npm run dev`): `twinlink demo --port 18700`.
const server = process.env.TWINLINK_URL ?? "http://127.0.0.1:18700";

// The server's API viewer (/docs) is Swagger UI 5 (it reads OpenAPI 3.1), from the pinned
// swagger-ui-dist, built into the package beside the app (apidocs/), so /docs works offline
// and loads nothing from a CDN. The server serves these two files at /docs/assets/.
const SWAGGER_FILES = ["swagger-ui-bundle.js", "swagger-ui.css"];

function apiViewer(): Plugin {
  const dist = dirname(createRequire(import.meta.url).resolve("swagger-ui-dist/package.json"));
  return {
    name: "twinlink-api-viewer",
    apply: "build",
    generateBundle() {
      for (const name of SWAGGER_FILES) {
        this.emitFile({ type: "asset", fileName: `apidocs/${name}`, source: readFileSync(join(dist, name)) });
      }
    },
  };
}

export default defineConfig({
  base: "/app/",
  plugins: [react(), apiViewer()],
  build: {
    outDir: "../src/twinlink/web/app",
    emptyOutDir: true,
    sourcemap: false,
  },
  server: {
    proxy: {
      "/api": { target: server, ws: true },
      "/twins": server,
      "/favicon.svg": server,
    },
  },
  test: {
    environment: "jsdom",
    globals: false,
    setupFiles: ["./src/test/setup.ts"],
    include: ["src/**/*.test.{ts,tsx}"],
    watch: false,
  },
});
