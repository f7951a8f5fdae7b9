/// <reference types="vitest" />
import { defineConfig } from "vite";
import react from "@vitejs/plugin-react";

// The server to develop against (`npm run dev`): `twinlink demo --port 18700`.
const server = process.env.TWINLINK_URL ?? "http://127.0.0.1:18700";

export default defineConfig({
  base: "/app/",
  plugins: [react()],
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
