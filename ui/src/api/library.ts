// The asset library's API (issue 16): assets by scope and kind, their immutable versions and
// tags, streamed upload and download.
import { apiFetch, apiRequest } from "./client";
import type { Schemas } from "./types";

export const KINDS = ["data", "models", "tools", "functions", "twins"] as const;
export type Kind = (typeof KINDS)[number];
export type ArchiveFormat = "tar" | "tgz" | "zip";
export type UploadFormat = ArchiveFormat | "file";

/** An asset as the list shows it: `versions` is how many it has, `tags` tag -> digest. */
export type Asset = Schemas["AssetView"];
export type LibraryFile = Schemas["FileView"];
export type VersionSummary = Schemas["VersionSummary"];
/** A version with its files. */
export type Version = Schemas["VersionView"];
/** An asset with its versions, newest first. */
export type AssetDetails = Schemas["AssetDetail"];
export type PushAnswer = Schemas["PushAnswer"];

const enc = encodeURIComponent;
const BASE = "/api/v1/library";

/** The URL path of an asset: scopes are written as they are (`group:ntnu`), encoded. */
export function assetPath(scope: string, kind: string, name: string): string {
  return `${BASE}/${enc(scope)}/${enc(kind)}/${enc(name)}`;
}

export interface AssetQuery {
  kind?: string;
  scope?: string;
  q?: string;
  limit?: number;
}

export async function listAssets(query: AssetQuery, signal?: AbortSignal): Promise<Asset[]> {
  const answer = await apiFetch<{ assets: Asset[] }>(BASE, {
    query: { kind: query.kind, scope: query.scope, q: query.q, limit: query.limit ?? 200 },
    signal,
  });
  return answer.assets;
}

export function getAsset(scope: string, kind: string, name: string, signal?: AbortSignal): Promise<AssetDetails> {
  return apiFetch<AssetDetails>(assetPath(scope, kind, name), { signal });
}

export function getVersion(scope: string, kind: string, name: string, ref: string, signal?: AbortSignal): Promise<Version> {
  return apiFetch<Version>(`${assetPath(scope, kind, name)}/versions/${enc(ref)}`, { signal });
}

export function deleteVersion(scope: string, kind: string, name: string, ref: string): Promise<void> {
  return apiFetch<void>(`${assetPath(scope, kind, name)}/versions/${enc(ref)}`, { method: "DELETE" });
}

export function deleteAsset(scope: string, kind: string, name: string): Promise<void> {
  return apiFetch<void>(assetPath(scope, kind, name), { method: "DELETE" });
}

/** Point `tag` at a version (it is moved when it is set). */
export function setTag(scope: string, kind: string, name: string, tag: string, version: string): Promise<Asset> {
  return apiFetch<Asset>(`${assetPath(scope, kind, name)}/tags/${enc(tag)}`, { method: "PUT", json: { version } });
}

/** Remove a tag; the version stays. */
export function deleteTag(scope: string, kind: string, name: string, tag: string): Promise<void> {
  return apiFetch<void>(`${assetPath(scope, kind, name)}/tags/${enc(tag)}`, { method: "DELETE" });
}

/** One file of a version, as text (twin.yaml, a README). */
export async function readVersionFile(
  scope: string,
  kind: string,
  name: string,
  ref: string,
  path: string,
  signal?: AbortSignal,
): Promise<string> {
  const filePath = path.split("/").map(enc).join("/");
  const response = await apiRequest(`${assetPath(scope, kind, name)}/versions/${enc(ref)}/files/${filePath}`, {
    accept: "*/*",
    signal,
  });
  return response.text();
}

/** The upload format a file's name says: an archive is unpacked, anything else is one file. */
export function formatOf(filename: string): UploadFormat {
  const lower = filename.toLowerCase();
  if (lower.endsWith(".zip")) return "zip";
  if (lower.endsWith(".tar.gz") || lower.endsWith(".tgz")) return "tgz";
  if (lower.endsWith(".tar")) return "tar";
  return "file";
}

export interface Upload {
  scope: string;
  kind: string;
  name: string;
  file: File;
  format: UploadFormat;
  tags: string[];
}

/** Push a version: the File is the request body, so the browser streams it from disk. */
export function pushVersion(upload: Upload, signal?: AbortSignal): Promise<PushAnswer> {
  const params = new URLSearchParams({ format: upload.format });
  if (upload.format === "file") params.set("filename", upload.file.name);
  for (const tag of upload.tags) params.append("tag", tag);
  return apiFetch<PushAnswer>(`${assetPath(upload.scope, upload.kind, upload.name)}/versions?${params}`, {
    method: "POST",
    body: upload.file,
    contentType: "application/octet-stream",
    signal,
  });
}

/** The archive's file name from Content-Disposition, else `<name>-<short digest>.<ext>`. */
export function archiveName(disposition: string | null, name: string, digest: string, format: ArchiveFormat): string {
  const match = disposition?.match(/filename\*?=(?:UTF-8'')?"?([^";]+)"?/i);
  if (match?.[1]) return decodeURIComponent(match[1]);
  const short = digest.replace(/^sha256:/, "").slice(0, 12);
  return `${name}-${short}.${format === "tgz" ? "tar.gz" : format}`;
}

/** Download a version's archive: fetched with the token (a plain link would carry none),
 * then saved from a blob URL. */
export async function downloadArchive(
  scope: string,
  kind: string,
  name: string,
  digest: string,
  format: ArchiveFormat,
): Promise<void> {
  const response = await apiRequest(`${assetPath(scope, kind, name)}/versions/${enc(digest)}/archive`, {
    query: { format },
    accept: "*/*",
  });
  const blob = await response.blob();
  const url = URL.createObjectURL(blob);
  try {
    const link = document.createElement("a");
    link.href = url;
    link.download = archiveName(response.headers.get("content-disposition"), name, digest, format);
    document.body.appendChild(link);
    link.click();
    link.remove();
  } finally {
    // the click has handed the blob to the download; revoke after the current task
    setTimeout(() => URL.revokeObjectURL(url), 0);
  }
}

/** A short form of a digest for tables: "sha256:0123456789ab". */
export function shortDigest(digest: string): string {
  return digest.startsWith("sha256:") ? digest.slice(0, 19) : digest.slice(0, 12);
}

/** A byte count as people read it. */
export function formatBytes(bytes: number): string {
  if (bytes < 1024) return `${bytes} B`;
  const units = ["KiB", "MiB", "GiB", "TiB"];
  let value = bytes / 1024;
  let unit = 0;
  while (value >= 1024 && unit < units.length - 1) {
    value /= 1024;
    unit += 1;
  }
  return `${value.toFixed(value < 10 ? 1 : 0)} ${units[unit]}`;
}
