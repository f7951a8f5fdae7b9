// The package "cart": library assets picked on the Library page to compose a twin package
// from (the DTaaS users' request), and the twin.yaml written from them. The cart lives in the
// tab's sessionStorage, so it survives going to another page and back.
import { useCallback, useEffect, useState } from "react";
import type { Asset } from "../../api/library";

export interface CartItem {
  /** The name the package gives it: ${assets.ALIAS} in its templates, assets/ALIAS/ in runs. */
  alias: string;
  /** lib:<scope>/<kind>/<name>@<tag or digest> */
  ref: string;
}

const KEY = "twinlink.package-cart";
export const ALIAS = /^[A-Za-z_][A-Za-z0-9_-]{0,63}$/;

/** An alias from an asset's name: "tingen-beam" -> "tingen_beam" (a name templates can use). */
export function aliasFor(name: string, taken: string[]): string {
  const base =
    name
      .replace(/[^A-Za-z0-9_]+/g, "_")
      .replace(/^[^A-Za-z]+|_+$/g, "")
      .slice(0, 60) || "asset";
  let alias = base;
  for (let n = 2; taken.includes(alias); n++) alias = `${base}_${n}`;
  return alias;
}

/** The reference a package names an asset by: its `latest` tag, else its newest version. */
export function cartRef(asset: Pick<Asset, "ref" | "tags" | "latest">): string {
  const version = asset.tags.latest ? "latest" : (asset.latest ?? "latest");
  return `lib:${asset.ref}@${version}`;
}

/** A YAML scalar for any text: a JSON string is one. */
const q = (text: string) => JSON.stringify(text);

/** A twin.yaml naming the cart's assets, with a document to start from. */
export function twinYamlFor(items: CartItem[], description: string): string {
  const lines = [
    "# A twin package composed on the Library page. Add parameters, devices, processors,",
    "# connectors and services as docs/deployments.md describes, then push it.",
    `description: ${q(description || "A twin composed from library assets")}`,
  ];
  if (items.length) {
    lines.push("assets:");
    for (const item of items) lines.push(`  ${item.alias}: ${q(item.ref)}`);
  }
  lines.push(
    "document:",
    '  version: "1.0"',
    `  name: ${q("${deployment.name}")}`,
    `  description: ${q(description || "A twin composed from library assets")}`,
  );
  return `${lines.join("\n")}\n`;
}

function load(): CartItem[] {
  try {
    const parsed: unknown = JSON.parse(sessionStorage.getItem(KEY) ?? "[]");
    return Array.isArray(parsed) ? (parsed as CartItem[]).filter((i) => typeof i?.alias === "string" && typeof i?.ref === "string") : [];
  } catch {
    return [];
  }
}

/** The cart and what changes it. */
export function useCart() {
  const [items, setItems] = useState<CartItem[]>(load);
  useEffect(() => sessionStorage.setItem(KEY, JSON.stringify(items)), [items]);
  const add = useCallback(
    (asset: Asset) =>
      setItems((cart) =>
        cart.some((i) => i.ref.startsWith(`lib:${asset.ref}@`))
          ? cart
          : [...cart, { alias: aliasFor(asset.name, cart.map((i) => i.alias)), ref: cartRef(asset) }],
      ),
    [],
  );
  const remove = useCallback((index: number) => setItems((cart) => cart.filter((_, i) => i !== index)), []);
  const rename = useCallback((index: number, alias: string) => setItems((cart) => cart.map((item, i) => (i === index ? { ...item, alias } : item))), []);
  const clear = useCallback(() => setItems([]), []);
  return { items, add, remove, rename, clear };
}
