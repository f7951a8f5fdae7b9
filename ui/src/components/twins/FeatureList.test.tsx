import { describe, expect, it } from "vitest";
import { fireEvent, render, screen, within } from "@testing-library/react";
import { FeatureList } from "./FeatureList";
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

    const monitoring = cards[1]!;
    expect(within(monitoring).getByRole("link")).toHaveAttribute("href", "https://crane-monitoring.example/");
    expect(within(monitoring).queryByRole("button", { name: "Try it" })).not.toBeInTheDocument();
  });

  it("has an empty state", () => {
    render(<FeatureList slug="x" features={[]} services={[]} />);
    expect(screen.getByText(/no features/)).toBeInTheDocument();
  });
});

describe("serviceNameOf", () => {
  it("follows the gateway's naming", () => {
    expect(serviceNameOf("Sensor manager")).toBe("sensor-manager");
    expect(serviceNameOf("OPC UA server")).toBe("opc-ua-server");
    expect(serviceNameOf("  CAD / store!! ")).toBe("cad-store");
  });
});
