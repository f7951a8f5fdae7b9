import { Empty } from "../../components/common/Status";
import { useTwin } from "./context";

export function ProcessorsTab() {
  const { twin } = useTwin();
  return <Empty>Processors of {twin.name}: coming soon.</Empty>;
}
