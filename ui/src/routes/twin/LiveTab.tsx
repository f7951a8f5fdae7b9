import { Empty } from "../../components/common/Status";
import { useTwin } from "./context";

export function LiveTab() {
  const { twin } = useTwin();
  return <Empty>Live of {twin.name}: coming soon.</Empty>;
}
