"""The ROS layer: private masters, node parameters and clocks, bags, catkin workspaces, demos and trials."""
