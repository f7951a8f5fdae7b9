import { describe, expect, it } from "vitest";
import { render } from "@testing-library/react";
import { nameParts, WordBreaks } from "./WordBreaks";

describe("WordBreaks", () => {
  it("breaks names between their words only", () => {
    expect(nameParts("Cantilever_Angle_radians")).toEqual(["Cantilever_", "Angle_", "radians"]);
    expect(nameParts("bridgePosition.x")).toEqual(["bridge", "Position.", "x"]);
    expect(nameParts("ns=2;s=Crane/Hoist-Load")).toEqual(["ns=2;s=Crane/", "Hoist-", "Load"]);
    expect(nameParts("UPPER")).toEqual(["UPPER"]);
  });

  it("renders the name whole, with break opportunities", () => {
    const { container } = render(<WordBreaks text="Tip_Angular_Rate" />);
    expect(container.textContent).toBe("Tip_Angular_Rate");
    expect(container.innerHTML).toBe("Tip_<wbr>Angular_<wbr>Rate");
  });
});
