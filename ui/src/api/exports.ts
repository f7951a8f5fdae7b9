// A twin's document in the exchange formats the server converts it to (docs/formats.md):
// fetched with the token (a plain link would carry none, and a private twin needs one), then
// saved from a blob URL.

import { apiRequest } from "./client";
import { fileNameFrom, saveBlob } from "./history";

export type TwinExportFormat = "yaml" | "json" | "wot-td" | "dtdl" | "aas-json" | "aasx";

interface ExportKind {
  label: string;
  accept: string;
  /** The file name's ending after the slug, when the server names no file. */
  suffix: string;
}

export const TWIN_EXPORTS: Record<TwinExportFormat, ExportKind> = {
  yaml: { label: "YAML", accept: "application/yaml", suffix: ".yaml" },
  json: { label: "JSON", accept: "application/json", suffix: ".json" },
  "wot-td": { label: "WoT TD", accept: "application/td+json", suffix: ".td.json" },
  dtdl: { label: "DTDL", accept: "application/ld+json", suffix: ".dtdl.json" },
  "aas-json": { label: "AAS JSON", accept: "application/json", suffix: ".aas.json" },
  aasx: { label: "AASX", accept: "application/asset-administration-shell-package+xml", suffix: ".aasx" },
};

/** Where the server serves one format: `?format=` on the canonical URL, the AASX package at
 * its own path. */
export function twinExportRequest(slug: string, format: TwinExportFormat): { path: string; query: Record<string, string> } {
  const base = `/twins/${encodeURIComponent(slug)}`;
  return format === "aasx" ? { path: `${base}/export.aasx`, query: {} } : { path: base, query: { format } };
}

/** Download the twin's document in `format`; answers the file name it was saved under. */
export async function downloadTwinExport(slug: string, format: TwinExportFormat): Promise<string> {
  const { path, query } = twinExportRequest(slug, format);
  const response = await apiRequest(path, { query, accept: TWIN_EXPORTS[format].accept });
  const blob = await response.blob();
  const name = fileNameFrom(response.headers.get("Content-Disposition")) ?? `${slug}${TWIN_EXPORTS[format].suffix}`;
  saveBlob(blob, name);
  return name;
}
