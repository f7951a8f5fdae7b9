// A feature's place on its twin's page, `/twins/{slug}#feature-{anchor}`. Search hits link
// there and the feature list gives its cards these ids, so both sides use this one function.

/** The anchor of a feature name: lower-case letters and digits (accents dropped, any script
 * kept) joined by single hyphens, e.g. "CAD store" → "cad-store". */
export function featureAnchor(name: string): string {
  const slug = name
    .normalize("NFKD")
    .replace(/\p{M}+/gu, "")
    .toLowerCase()
    .replace(/[^\p{L}\p{N}]+/gu, "-")
    .replace(/^-+|-+$/g, "");
  return slug || "feature";
}

/** The element id of a feature card. */
export function featureElementId(name: string): string {
  return `feature-${featureAnchor(name)}`;
}

/** The link to a feature on its twin's page. */
export function featureHref(slug: string, featureName: string): string {
  return `/twins/${encodeURIComponent(slug)}#${featureElementId(featureName)}`;
}

/** The element id a location hash ("#feature-cad-store", perhaps percent-encoded) points at. */
export function hashTarget(hash: string): string {
  const raw = hash.startsWith("#") ? hash.slice(1) : hash;
  try {
    return decodeURIComponent(raw);
  } catch {
    return raw;
  }
}
