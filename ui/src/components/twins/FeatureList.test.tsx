import { afterEach, describe, expect, it, vi } from "vitest";
import { fireEvent, render, screen, within } from "@testing-library/react";
import { FeatureList, featureElementIds } from "./FeatureList";
import { featureAnchor, featureHref, hashTarget } from "./featureAnchor";
import { serviceNameOf } from "../../api/gateway";
import type { Feature, Service } from "../../api/types";

const features: Feature[] = [
  {
    name: "OPC UA server",
    description: "OPC UA server wired to the crane's PLC.",
    address: "opc.tcp://127.0.0.1:4840/ilmatar/",
    apiAddress: "http://127.0.0.1:8703/api/",
    documentation: "http://127.0.0.1:8703/docs",
    keywords: ["real-time", "PLC"],
  },
  { name: "Manufacturer monitoring", address: "https://crane-monitoring.example/" },
];

const services = [
  {
    name: "opc-ua-server",
    feature: "OPC UA server",
    methods: ["GET"],
    health_path: "variables",
    blocked: null,
    health: { checked_at: 1, path: "variables", status: "up", http_status: 200, ms: 3 },
  },
] as unknown as Service[];

describe("FeatureList", () => {
  it("renders each feature with its links, keywords and, for services, health and Try it", () => {
    render(<FeatureList slug="ilmatar-k16052" features={features} services={services} />);
    const cards = screen.getAllByRole("listitem");
    expect(cards).toHaveLength(2);

    const opc = cards[0]!;
    expect(within(opc).getByRole("heading", { name: "OPC UA server" })).toBeInTheDocument();
    // opc.tcp: is not a web link; the documentation is
    expect(within(opc).getByText("opc.tcp://127.0.0.1:4840/ilmatar/").tagName).toBe("SPAN");
    expect(within(opc).getByRole("link", { name: "http://127.0.0.1:8703/docs" })).toHaveAttribute(
      "href",
      "http://127.0.0.1:8703/docs",
    );
    expect(within(opc).getByText("PLC")).toBeInTheDocument();
    expect(within(opc).getByText("service opc-ua-server")).toBeInTheDocument();
    expect(within(opc).getByText("up")).toBeInTheDocument();
    fireEvent.click(within(opc).getByRole("button", { name: "Try it" }));
    expect(within(opc).getByLabelText("Path")).toHaveValue("variables");

    expect(within(opc).queryByText("described only")).not.toBeInTheDocument();

    // No apiAddress: described only, nothing to try
    const monitoring = cards[1]!;
    expect(within(monitoring).getByRole("link")).toHaveAttribute("href", "https://crane-monitoring.example/");
    expect(within(monitoring).getByText("described only")).toBeInTheDocument();
    expect(within(monitoring).queryByRole("button", { name: "Try it" })).not.toBeInTheDocument();
  });

  it("gives each card an id, and scrolls to and highlights the one the hash names", () => {
    const scrollIntoView = vi.fn();
    Element.prototype.scrollIntoView = scrollIntoView;
    const list = (hash: string) => <FeatureList slug="ilmatar-k16052" features={features} services={[]} hash={hash} />;
    const { rerender } = render(list("#feature-manufacturer-monitoring"));
    const [opc, monitoring] = screen.getAllByRole("listitem");
    expect(opc).toHaveAttribute("id", "feature-opc-ua-server");
    expect(opc).not.toHaveClass("feature-target");
    expect(monitoring).toHaveAttribute("id", "feature-manufacturer-monitoring");
    expect(monitoring).toHaveClass("feature-target");
    expect(scrollIntoView).toHaveBeenCalledTimes(1);
    expect(scrollIntoView.mock.contexts[0]).toBe(monitoring);

    // another hash moves the highlight; one naming no card highlights none
    rerender(list("#feature-opc-ua-server"));
    expect(opc).toHaveClass("feature-target");
    expect(monitoring).not.toHaveClass("feature-target");
    rerender(list("#history"));
    expect(document.querySelector(".feature-target")).toBeNull();
  });

  it("has an empty state", () => {
    render(<FeatureList slug="x" features={[]} services={[]} />);
    expect(screen.getByText(/no features/)).toBeInTheDocument();
  });
});

afterEach(() => {
  delete (Element.prototype as { scrollIntoView?: unknown }).scrollIntoView;
});

describe("featureAnchor", () => {
  it("is the same on the search link and the card", () => {
    expect(featureAnchor("CAD store")).toBe("cad-store");
    expect(featureAnchor("  Käyttö / Historian!! ")).toBe("kaytto-historian");
    expect(featureAnchor("!!!")).toBe("feature");
    expect(featureHref("ilmatar k16052", "CAD store")).toBe("/twins/ilmatar%20k16052#feature-cad-store");
    expect(featureElementIds([{ name: "CAD store" }])).toEqual(["feature-cad-store"]);
  });

  it("keeps repeated names apart and reads percent-encoded hashes", () => {
    expect(featureElementIds([{ name: "Data" }, { name: "data" }, { name: "Data" }])).toEqual([
      "feature-data",
      "feature-data-2",
      "feature-data-3",
    ]);
    expect(hashTarget("#feature-%E6%95%B0%E6%8D%AE")).toBe("feature-数据");
    expect(featureAnchor("数据")).toBe("数据");
    expect(hashTarget("#bad-%E6")).toBe("bad-%E6");
  });
});

describe("serviceNameOf", () => {
  it("follows the gateway's naming", () => {
    expect(serviceNameOf("Sensor manager")).toBe("sensor-manager");
    expect(serviceNameOf("OPC UA server")).toBe("opc-ua-server");
    expect(serviceNameOf("  CAD / store!! ")).toBe("cad-store");
  });
});
