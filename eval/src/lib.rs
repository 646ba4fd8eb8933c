//! The official Argoverse 2 scenario-mining metrics. Not built yet (issue: eval).
