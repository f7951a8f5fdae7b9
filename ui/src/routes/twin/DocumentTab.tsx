import { Empty } from "../../components/common/Status";
import { useTwin } from "./context";

export function DocumentTab() {
  const { twin } = useTwin();
  return <Empty>Document of {twin.name}: coming soon.</Empty>;
}
