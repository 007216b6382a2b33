//! Recording a running world's data handlers (thesis 4.3.2): ring buffers on every robot
//! for live views, and robot 0's frames into a B.8 data file by the background writer.

use std::path::Path;

use bevy::prelude::*;

use crate::data::HandlerSpec;
use crate::data::store::DataStore;
use crate::sim::Simulator;
use crate::sim::datalog::{DataLog, DataSettings, DataSink, flush_round, handlers_for};
use crate::sim::error::SimError;
use crate::sim::kernel::Kernel;
use crate::sim::robot::SimRobot;
use crate::sim::tactile::RobotSensors;

impl Simulator {
    /// The data handlers robot `index` records (its modules', its sensors', `Robot_Data`).
    pub fn data_handlers(&self, index: usize) -> Result<Vec<HandlerSpec>, SimError> {
        Ok(handlers_for(self.kernel(index)?, self.sensors(index)?))
    }

    /// Starts recording data handlers on every robot into ring buffers; with `store`,
    /// robot 0's frames are also written to that data file by its background writer. Call
    /// [`Simulator::finish_data`] to close the file.
    pub fn enable_data(&mut self, settings: DataSettings, store: Option<DataStore>) {
        let world = self.world_mut();
        world.insert_resource(settings);
        let mut q = world.query::<(Entity, &SimRobot, &Kernel, &RobotSensors)>();
        let logs: Vec<(Entity, DataLog)> = q
            .iter(world)
            .map(|(e, robot, kernel, sensors)| {
                let mass = robot.bodies.iter().map(|(_, m)| m).sum();
                let handlers = handlers_for(&kernel.0, &sensors.0);
                (e, DataLog::new(handlers, &settings, mass))
            })
            .collect();
        for (e, log) in logs {
            world.entity_mut(e).insert(log);
        }
        if let Some(store) = store {
            world.insert_resource(DataSink {
                store,
                rounds_sent: 0,
                error: None,
            });
        }
    }

    /// Records every robot's handlers, and robot 0's into a new data file at `file`
    /// (created now; the error names it).
    pub fn record_to(&mut self, file: &Path, settings: DataSettings) -> Result<(), RecordError> {
        let handlers = self.data_handlers(0)?;
        let store = DataStore::create(file, handlers)?;
        self.enable_data(settings, Some(store));
        Ok(())
    }

    /// The data handlers of robot `index` (after [`Simulator::enable_data`]).
    pub fn data(&self, index: usize) -> Result<&DataLog, SimError> {
        self.robot_component::<DataLog>(index)
    }

    /// Sends the last frames to the data file and closes it well-formed; returns the
    /// rounds written (0 without a file).
    pub fn finish_data(&mut self) -> Result<u64, crate::data::store::DataStoreError> {
        let world = self.world_mut();
        flush_round(world);
        match world.remove_resource::<DataSink>() {
            Some(sink) => {
                if let Some(e) = sink.error {
                    return Err(e);
                }
                sink.store.finish()
            }
            None => Ok(0),
        }
    }
}

/// Why a data file could not be started.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// The world has no robot 0.
    #[error("{0}")]
    Sim(#[from] SimError),
    /// The file cannot be created.
    #[error("{0}")]
    Store(#[from] crate::data::store::DataStoreError),
}
