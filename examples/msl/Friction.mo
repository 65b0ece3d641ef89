within Modelica.Mechanics.Rotational.Examples;
model Friction "Drive train with clutch and brake"
  import Modelica.Constants.pi;
  extends Modelica.Icons.Example;
  parameter SI.Time startTime=0.5 "Start time of step";
  output SI.Torque tMotor=torque.tau "Driving torque";
  output SI.Torque tClutch=clutch.tau "Friction torque of clutch";
  output SI.Torque tBrake=brake.tau "Friction torque of brake";
  output SI.Torque tSpring=spring.tau "Spring torque";

  Rotational.Sources.Torque torque(useSupport=true)
    annotation (Placement(transformation(extent={{-45,-10},{-25,10}})));
  Rotational.Components.Inertia inertia3(
    J=1,
    phi(
      start=0,
      fixed=true,
      displayUnit="deg"),
    w(start=100,
      fixed=true,
      displayUnit="rad/s"))
    annotation (Placement(transformation(extent={{-15,-10},{5,10}})));
  Rotational.Components.Clutch clutch(fn_max=160)
    annotation (Placement(transformation(extent={{15,-10},{35,10}})));
  Rotational.Components.Inertia inertia2(
    J=0.05,
    phi(start=0, fixed=true),
    w(start=90, fixed=true))
    annotation (Placement(transformation(extent={{45,-10},{65,10}})));
  Rotational.Components.SpringDamper spring(c=160, d=1)
    annotation (Placement(transformation(extent={{75,-10},{95,10}})));
  Rotational.Components.Inertia inertia1(
    J=1,
    phi(start=0, fixed=true),
    w(start=90, fixed=true))
    annotation (Placement(transformation(extent={{135,-10},{155,10}})));
  Rotational.Components.Brake brake(fn_max=1600, useSupport=true)
    annotation (Placement(transformation(extent={{105,-10},{125,10}})));
  Modelica.Blocks.Sources.Constant const(k=1)
    annotation (Placement(transformation(origin={25,35}, extent={{-10,-10},{10,10}}, rotation=270)));
  Modelica.Blocks.Sources.Step step(startTime=startTime)
    annotation (Placement(transformation(origin={115,35}, extent={{-10,-10},{10,10}}, rotation=270)));
  Modelica.Blocks.Sources.Step step2(
    height=-1,
    offset=1,
    startTime=startTime)
    annotation (Placement(transformation(extent={{-160,-30},{-140,-10}})));
  Modelica.Blocks.Sources.Sine sine(amplitude=200, f=50/pi)
    annotation (Placement(transformation(extent={{-160,10},{-140,30}})));
  Modelica.Blocks.Math.Product product
    annotation (Placement(transformation(extent={{-120,-10},{-100,10}})));
  Rotational.Components.Fixed fixed
    annotation (Placement(transformation(extent={{-45,-40},{-25,-20}})));
equation
  connect(torque.flange, inertia3.flange_a) annotation (Line(points={{-25,0},{-15,0}}));
  connect(inertia3.flange_b, clutch.flange_a) annotation (Line(points={{5,0},{15,0}}));
  connect(clutch.flange_b, inertia2.flange_a) annotation (Line(points={{35,0},{45,0}}));
  connect(inertia2.flange_b, spring.flange_a) annotation (Line(points={{65,0},{75,0}}));
  connect(spring.flange_b, brake.flange_a) annotation (Line(points={{95,0},{105,0}}));
  connect(brake.flange_b, inertia1.flange_a) annotation (Line(points={{125,0},{135,0}}));
  connect(sine.y, product.u1) annotation (Line(points={{-139,20},{-130,20},{-130,6},{-122,6}}, color={0,0,127}));
  connect(step2.y, product.u2) annotation (Line(points={{-139,-20},{-130,-20},{-130,-6},{-122,-6}}, color={0,0,127}));
  connect(product.y, torque.tau) annotation (Line(points={{-99,0},{-47,0}}, color={0,0,127}));
  connect(const.y, clutch.f_normalized) annotation (Line(points={{25,24},{25,11}}, color={0,0,127}));
  connect(step.y, brake.f_normalized) annotation (Line(points={{115,24},{115,11}}, color={0,0,127}));
  connect(torque.support, fixed.flange) annotation (Line(points={{-35,-10},{-35,-30}}));
  connect(brake.support, fixed.flange) annotation (Line(points={{115,-10},{115,-30},{-35,-30}}));
  annotation (experiment(StopTime=3, Interval=0.0005, Tolerance=1e-06), Documentation(info="<html>
<p>This drive train contains a frictional <strong>clutch</strong> and a <strong>brake</strong>.
Simulate the system for 1 second using the following initial values
(defined already in the model): inertia1.w = 90, inertia2.w = 90, inertia3.w = 100.</p>
</html>"));
end Friction;
